r"""Pair geometry of particles on periodic and non-periodic axes: the separation ``x_i − x_j`` with the
minimum-image convention ``d ← d − L round(d/L)`` on a periodic axis of period ``L``, and the padded
(n, 3) layout the pair kernels read, so they carry no branch on the dimension.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

from partmesh.particle.positions import box_corners, periodicity, positions
from partmesh.particle.threads import PRANGE_ONLY

__all__ = ["FASTMATH", "image", "padded", "periods", "separation", "separations"]

#: numba's fastmath flags of the pair loops: every one but ``nsz`` (no signed zeros). With it beside
#: ``reassoc`` (``fastmath=True``), LLVM optimised sph's rates differently when numba compiled them in the run's
#: process and when it loaded them from its cache: a first run's results and a later run's differed in their last
#: bits (9e-13 of a unit acceleration), with the same code, seed and threads
FASTMATH = {"nnan", "ninf", "arcp", "afn", "contract", "reassoc"}


@numba.njit(cache=True, inline="always")
def image(d, box, half):
    """Minimum image of a separation |d| < 1.5·box (half = box/2 on a
    periodic axis, +inf otherwise); branch-free so the loops vectorise."""
    return d - box * ((d > half) - (d < -half))


@numba.njit(cache=True, inline="always")
def _nearest(d, box, half):
    """Minimum image of a separation |d| < 1.5·box, with branches: in the
    pair loops of the particle kernels they are always predicted (never
    taken on a non-periodic axis, where ``half`` is +inf), which is cheaper
    there than :func:`image`'s arithmetic."""
    if d > half:
        return d - box
    if d < -half:
        return d + box
    return d


@numba.njit(cache=True, inline="always")
def separation(x, i, j, box, half):
    """``(d0, d1, d2, r²)``: ``x_i − x_j`` per axis, the minimum image on
    periodic axes (positions within 1.5 periods of each other), and its
    squared length (a pair loop compares r² with the supports before it
    takes the root). ``x`` is (n, 3), zero beyond the problem's dimension
    (:func:`padded`), so the pair loops carry no branch on the dimension;
    ``box``, ``half`` from :func:`periods`. The one place the particle
    kernels get pair geometry from."""
    d0 = _nearest(x[i, 0] - x[j, 0], box[0], half[0])
    d1 = _nearest(x[i, 1] - x[j, 1], box[1], half[1])
    d2 = _nearest(x[i, 2] - x[j, 2], box[2], half[2])
    return d0, d1, d2, d0 * d0 + d1 * d1 + d2 * d2


def periods(lo, hi, periodic, dim):
    """``(box, half)`` for :func:`separation`, three entries each: the box
    size per axis and half the period on periodic axes (+inf elsewhere and
    beyond ``dim``)."""
    lo, hi = box_corners(lo, hi, dim)
    box, half = np.ones(3), np.full(3, np.inf)
    box[:dim] = hi - lo
    half[:dim] = np.where(periodicity(periodic, dim), 0.5 * box[:dim], np.inf)
    return box, half


def padded(a) -> np.ndarray:
    """(n, 3) contiguous float copy of positions or vectors ``a`` (n, dim),
    zero beyond ``dim``: the layout :func:`separation` and the pair kernels read."""
    a = np.asarray(a, dtype=np.float64)
    out = np.zeros((a.shape[0], 3))
    out[:, : a.shape[1]] = a
    return out


@numba.njit(cache=True, parallel=PRANGE_ONLY)
def _separations(x, offsets, index, box, half):
    """``x_i − x_j`` (the minimum image where ``half`` is finite, for
    positions any number of periods apart) and its length."""
    n, dim = x.shape
    dx = np.empty((index.size, dim))
    r = np.empty(index.size)
    for i in prange(n):
        for q in range(offsets[i], offsets[i + 1]):
            r2 = 0.0
            for a in range(dim):
                d = x[i, a] - x[index[q], a]
                if half[a] < math.inf:
                    d -= box[a] * math.floor(d / box[a] + 0.5)
                dx[q, a] = d
                r2 += d * d
            r[q] = math.sqrt(r2)
    return dx, r


def separations(x, offsets, index, lo, hi, periodic=False):
    """``(dx, r)`` of CSR neighbour lists: ``dx = x_i − x_j`` (m, dim),
    minimum image on periodic axes, and ``r = |dx|`` (m,)."""
    x = positions(x)
    box, half = periods(lo, hi, periodic, x.shape[1])
    return _separations(x, np.asarray(offsets, np.int64), np.asarray(index), box, half)
