"""Ghost cells for the domain boundaries, on primitive states (tuples of
arrays laid out ``([y,] x)``).

Kinds per side: ``reflect`` (mirror image, normal velocity negated: a slip
wall), ``outflow`` (zero gradient), ``periodic`` (wrap), ``inflow`` (the
imposed primitive state of the current time in every ghost cell).
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

N_GHOST = 2


def axis_of(ndim, d):
    """Array axis of spatial direction ``d`` (x is the last axis)."""
    return ndim - 1 - d


class SchemeAxes:
    """What a grid scheme of spacings ``dx`` (one per direction) answers
    about its arrays: the dimension and the array axis of each direction."""

    @property
    def dim(self) -> int:
        return len(self.dx)

    @property
    def axes(self) -> list[int]:
        """The array axis of each direction (x is the last axis)."""
        return [axis_of(self.dim, d) for d in range(self.dim)]


def _take(a, axis, start, stop, step=1):
    index = [slice(None)] * a.ndim
    index[axis] = slice(start, stop, step)
    return a[tuple(index)]


def ghost_layer(a, axis, side, kind, value=None, flip=False, ng=N_GHOST):
    """The ``ng`` ghost cells of one variable ``a`` beyond the ``side`` ('lo'
    or 'hi') boundary along ``axis``, ordered like the cells. ``flip``
    negates a reflected variable (the normal velocity); ``value`` is the
    inflow value."""
    n = a.shape[axis]
    if kind == "periodic":
        if n < ng:  # fewer cells than ghosts: the images wrap more than once
            return jnp.take(a, (np.arange(ng) - ng if side == "lo" else np.arange(ng)) % n, axis=axis)
        return _take(a, axis, n - ng, n) if side == "lo" else _take(a, axis, 0, ng)
    if kind == "outflow":
        edge = _take(a, axis, 0, 1) if side == "lo" else _take(a, axis, n - 1, n)
        return jnp.repeat(edge, ng, axis=axis)
    if kind == "reflect":
        if n < ng:  # fewer cells than ghosts: the mirror images fold back at the far side too
            fold = np.arange(ng) % (2 * n)
            fold = np.where(fold < n, fold, 2 * n - 1 - fold)
            mirror = jnp.take(a, fold[::-1] if side == "lo" else n - 1 - fold, axis=axis)
        else:
            mirror = (_take(a, axis, ng - 1, None, -1) if side == "lo" else
                      _take(a, axis, n - 1, n - ng - 1 if n > ng else None, -1))
        return -mirror if flip else mirror
    if kind == "inflow":
        shape = list(a.shape)
        shape[axis] = ng
        return jnp.full(shape, value, dtype=a.dtype)
    raise ValueError(f"unknown boundary kind {kind!r}")


def with_ghosts(W, kinds, states, ng=N_GHOST, directions=None):
    """The primitive state ``W`` padded with ``ng`` ghost cells on every side.

    ``kinds`` lists the boundary kind of each side in the order x_lo, x_hi,
    y_lo, y_hi; ``states[i]`` is the primitive inflow state of side ``i``
    (a row of a small array; used by ``inflow`` sides only). Directions are
    padded in turn (x, then y), so corner ghosts take the y-rule applied to
    x-ghosts; ``directions`` (all if None) pads along those only.
    """
    dim = W[0].ndim
    for d in range(dim) if directions is None else directions:
        axis = axis_of(dim, d)
        padded = []
        for k, a in enumerate(W):
            flip = k == 1 + d
            lo = ghost_layer(a, axis, "lo", kinds[2 * d], states[2 * d, k], flip, ng)
            hi = ghost_layer(a, axis, "hi", kinds[2 * d + 1], states[2 * d + 1, k], flip, ng)
            padded.append(jnp.concatenate([lo, a, hi], axis=axis))
        W = tuple(padded)
    return W
