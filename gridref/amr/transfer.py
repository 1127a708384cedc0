"""Moving a state between levels of ratio 2, conserving it.

Restriction (fine → coarse): a coarse cell takes the mean of its ``2^dim``
children, so a level's total is unchanged (Berger & Colella 1989, §3.3);
in a geometry of revolution and around bodies, the mean weighted by the
children's (open) volumes.

Prolongation (coarse → fine): each child takes its parent's value plus the
parent's limited slope times the offset of its centre, ±¼ of the parent's
cell along every axis: the children's mean is the parent's value, so the
prolonged state holds the coarse one's totals; the slopes are limited with
the monotonized central limiter (van Leer 1977), so no child leaves the
range of its parent's neighbours (conservative limited linear
interpolation, as AMReX's ``cell_cons_interp``). A parent whose children
would not all be admissible (``admissible``: for a gas, positive density
and pressure) passes its own value to every child instead. In a geometry
of revolution the two children along the radius differ in volume,
``v_l < v_r``: their offsets become ``±¼ − c`` with
``c = (v_r − v_l) / (4 (v_l + v_r))``, so that their volume-weighted mean
is still the parent's value (``|c| < ¼``: no child leaves the range).
"""

from __future__ import annotations

import jax.numpy as jnp

from partmesh.gridref.euler.reconstruct import monotonized_central


def _crop(a, axis, lo, hi):
    index = [slice(None)] * a.ndim
    index[axis] = slice(lo, a.shape[axis] - hi)
    return a[tuple(index)]


def repeated(a, k: int):
    """Every cell of ``a`` (a numpy or JAX array) repeated ``k`` times along every axis."""
    for axis in range(a.ndim):
        a = a.repeat(k, axis=axis)
    return a


def _doubled(a):
    return repeated(a, 2)


def _offsets(n: int, axis: int, ndim: int, shift=None):
    """The children's offsets ±¼ along ``axis`` of an array of ``n`` children
    there, less each parent's ``shift`` (``n/2`` values; none if None)."""
    shape = [1] * ndim
    shape[axis] = n
    offsets = jnp.tile(jnp.array([-0.25, 0.25]), n // 2)
    if shift is not None:
        offsets = offsets - jnp.repeat(shift, 2)
    return offsets.reshape(shape)


def volume_shift(v_lo, v_hi):
    """``c = (v_r − v_l) / (4 (v_l + v_r))``: the shift of the offsets of two
    children of volumes ``v_lo``, ``v_hi`` along the radius that keeps
    their volume-weighted mean the parent's value."""
    return (v_hi - v_lo) / (4.0 * (v_lo + v_hi))


def prolonged(window, admissible=None, shift=None):
    """The children of the interior cells of a coarse ``window`` (a tuple
    over variables of arrays with one ghost cell on every side, laid out
    ``([y,] x)``, of any shape): arrays twice the interior's size along
    every axis. ``shift``: per interior parent along x, the shift of its
    children's offsets along x (:func:`volume_shift`; None: planar)."""
    ndim = window[0].ndim
    inner = [_crop_all(a) for a in window]
    slopes = []
    for a in window:
        per_axis = []
        for axis in range(ndim):
            others = _crop_others(a, axis)
            per_axis.append(monotonized_central(_crop(others, axis, 1, 1) - _crop(others, axis, 0, 2),
                                                _crop(others, axis, 2, 0) - _crop(others, axis, 1, 1)))
        slopes.append(per_axis)
    radial = ndim - 1  # x, the radius in a geometry of revolution
    linear = [_doubled(c) + sum(_doubled(s) * _offsets(2 * c.shape[axis], axis, ndim,
                                                      shift if axis == radial else None)
                                for axis, s in enumerate(per_axis))
              for c, per_axis in zip(inner, slopes)]
    if admissible is None:
        return tuple(linear)
    ok = admissible(tuple(linear))
    for axis in range(ndim):  # a parent's children all linear, or all its own value
        shape = list(ok.shape)
        shape[axis:axis + 1] = [shape[axis] // 2, 2]
        ok = jnp.all(ok.reshape(shape), axis=axis + 1)
    ok = _doubled(ok)
    return tuple(jnp.where(ok, f, _doubled(c)) for f, c in zip(linear, inner))


def _crop_all(a):
    for axis in range(a.ndim):
        a = _crop(a, axis, 1, 1)
    return a


def _crop_others(a, axis):
    for other in range(a.ndim):
        if other != axis:
            a = _crop(a, other, 1, 1)
    return a


def restricted(block, volumes=None):
    """The means of the ``2^dim`` children of every coarse cell over a fine
    ``block`` (an array laid out ``([y,] x)``): half its size along every
    axis; weighted by the children's ``volumes`` (broadcast to the block:
    their open volumes around a body, along x their rings in a geometry of
    revolution; None: all equal), the plain mean where they are all zero."""
    shape = []
    for n in block.shape:
        shape += [n // 2, 2]
    children = tuple(range(1, 2 * block.ndim, 2))
    mean = jnp.mean(block.reshape(shape), axis=children)
    if volumes is None:
        return mean
    w = jnp.broadcast_to(volumes, block.shape).reshape(shape)
    total = jnp.sum(w, axis=children)
    return jnp.where(total > 0.0, jnp.sum(block.reshape(shape) * w, axis=children) / jnp.where(total > 0.0, total, 1.0),
                     mean)
