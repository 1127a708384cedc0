"""Where a level needs a finer one: Löhner's error estimator and the
relative variation.

For a variable q and each axis, the normalised second difference::

    E = |q₊ − 2q + q₋| / (|q₊ − q| + |q − q₋| + ε (|q₊| + 2|q| + |q₋|)),

0 where q is linear, near 1 at a jump; ε = 0.01 filters ripples of a
relative size below it (Löhner 1987, Comput. Methods Appl. Mech. Eng. 61,
323; as FLASH's refinement criterion with ``refine_filter`` 0.01). A cell's
estimate is the largest over the axes and the variables the method names
(the Euler solver: density and pressure).

Löhner's estimate finds jumps and kinks and passes over smooth regions,
however steep, where the coarser level's error is that of a smooth flow at
twice the spacing (a rarefaction of Sod's tube on the coarser level holds
a third of the uniform grid's L1 error more). The relative variation::

    V = |q₊ − q₋| / (|q₊| + 2|q| + |q₋|),

about half the relative change across a cell, flags those: a cell of a
level whose V passes ``gradient`` asks for the next finer level too.
"""

from __future__ import annotations

import jax.numpy as jnp

#: ε, the noise filter of the estimator
FILTER = 0.01


def _shifted(q, axis, lo, hi):
    index = [slice(1, n - 1) for n in q.shape]
    index[axis] = slice(lo, q.shape[axis] - hi)
    return q[tuple(index)]


def lohner(q):
    """Löhner's estimate of every interior cell of ``q`` (an array with one
    ghost cell on every side), the largest over the axes."""
    estimate = 0.0
    for axis in range(q.ndim):
        lo, mid, hi = _shifted(q, axis, 0, 2), _shifted(q, axis, 1, 1), _shifted(q, axis, 2, 0)
        scale = jnp.abs(hi - mid) + jnp.abs(mid - lo) + FILTER * (jnp.abs(hi) + 2.0 * jnp.abs(mid) + jnp.abs(lo))
        e = jnp.abs(hi - 2.0 * mid + lo) / jnp.where(scale > 0.0, scale, 1.0)
        estimate = jnp.maximum(estimate, e)
    return estimate


def variation(q):
    """The relative variation ``V`` of every interior cell of ``q`` (an array
    with one ghost cell on every side), the largest over the axes."""
    estimate = 0.0
    for axis in range(q.ndim):
        lo, mid, hi = _shifted(q, axis, 0, 2), _shifted(q, axis, 1, 1), _shifted(q, axis, 2, 0)
        scale = jnp.abs(hi) + 2.0 * jnp.abs(mid) + jnp.abs(lo)
        estimate = jnp.maximum(estimate, jnp.abs(hi - lo) / jnp.where(scale > 0.0, scale, 1.0))
    return estimate


def child_maxima(estimate):
    """The largest estimate over each half of a block along every axis:
    an array of 2 per axis (a block's children, laid out ``([y,] x)``)."""
    shape = []
    for n in estimate.shape:
        shape += [2, n // 2]
    return jnp.max(estimate.reshape(shape), axis=tuple(range(1, 2 * estimate.ndim, 2)))
