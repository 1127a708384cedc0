r"""Cell grids over particles: the cell of every particle, a stable counting sort by cell, and what the
neighbour search (:mod:`partmesh.particle.neighbours`) and the particle solvers build on them.

A grid of cells no narrower than a given size covers the box ``[lo, hi)`` on periodic axes and the
bounding box of the box and the particles elsewhere; cells are numbered ``(cz·ny + cy)·nx + cx``
(x fastest), and a counting sort lists the particles cell by cell in O(N)
(Hockney & Eastwood 1988, *Computer simulation using particles*, §8-4).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

from partmesh.cases.errors import InputError
from partmesh.particle.positions import box_corners, ordered_box, periodicity, positions
from partmesh.particle.threads import PRANGE_ONLY

__all__ = ["CELL_MARGIN", "cell_grid", "cell_ids", "cell_support", "counting_sort", "nearby_maximum", "sort_order"]

# Cells are made this much wider than the size asked for, so that a particle put
# one cell off by round-off still finds every neighbour.
CELL_MARGIN = 1.0 + 1e-9


@numba.njit(cache=True, inline="always")
def _cell_index(xa, origin, width, ncell, per):
    """Cell index of coordinate ``xa`` along one axis (wrapped or clamped)."""
    c = math.floor((xa - origin) / width)
    if per:
        c = c % ncell
        if c < 0:
            c += ncell
    else:
        if c < 0:
            c = 0
        elif c >= ncell:
            c = ncell - 1
    return c


@numba.njit(cache=True, parallel=PRANGE_ONLY)
def cell_ids(x, origin, width, ncell, per):
    """Linear cell id ``(cz·ny + cy)·nx + cx`` of every particle."""
    n, dim = x.shape
    cid = np.empty(n, dtype=np.int64)
    for i in prange(n):
        c = 0
        for a in range(dim - 1, -1, -1):
            c = c * ncell[a] + _cell_index(x[i, a], origin[a], width[a], ncell[a], per[a])
        cid[i] = c
    return cid


@numba.njit(cache=True)
def counting_sort(cid, ntot):
    """Stable counting sort: ``order`` lists particles cell by cell (index
    order within a cell); ``start[c]:start[c+1]`` is cell c's slice."""
    n = cid.size
    start = np.zeros(ntot + 1, dtype=np.int64)
    for i in range(n):
        start[cid[i] + 1] += 1
    for c in range(ntot):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        c = cid[i]
        order[fill[c]] = i
        fill[c] += 1
    return start, order


@numba.njit(cache=True)
def _cell_maxima(cid, values, ntot):
    """Column by column, the largest of ``values`` (n, k) in each of the
    ``ntot`` cells (−inf in an empty cell)."""
    n, k = values.shape
    out = np.full((ntot, k), -np.inf)
    for i in range(n):
        c = cid[i]
        for j in range(k):
            if values[i, j] > out[c, j]:
                out[c, j] = values[i, j]
    return out


def cell_grid(x, lo, hi, periodic, cell_size):
    """Cell grid used by the search: ``(origin, width, ncell, per, box)``, each of length 3.

    Along a periodic axis the grid covers ``[lo, hi)`` with
    ``ncell = floor((hi − lo) / cell_size)`` cells (at least 1); along a
    non-periodic axis it covers the bounding box of ``[lo, hi]`` and the
    particles. Cells are at least ``cell_size`` wide. Unused axes (beyond
    ``dim``) get one cell. The total cell count is capped near ``4 n + 64``
    by widening the cells, so a stray particle far away cannot blow up memory.
    """
    n, dim = x.shape
    origin = np.zeros(3)
    extent = np.ones(3)
    per = np.zeros(3, dtype=np.bool_)
    box = np.ones(3)
    for a in range(dim):
        per[a] = bool(periodic[a])
        if per[a]:
            origin[a] = lo[a]
            extent[a] = hi[a] - lo[a]
            box[a] = hi[a] - lo[a]
        else:
            lo_a = min(lo[a], x[:, a].min()) if n else lo[a]
            hi_a = max(hi[a], x[:, a].max()) if n else hi[a]
            origin[a] = lo_a
            extent[a] = max(hi_a - lo_a, np.finfo(float).tiny)
            box[a] = extent[a]
    cs = float(cell_size) * CELL_MARGIN
    cap = 4 * n + 64
    while True:
        ncell = np.ones(3, dtype=np.int64)
        for a in range(dim):
            ncell[a] = max(1, min(int(extent[a] / cs), 2**40))
        if int(np.prod(ncell.astype(np.float64))) <= cap:
            break
        cs *= 1.25
    width = extent / ncell
    return origin, width, ncell, per, box


def cell_support(H) -> float:
    """The support the cells are sized for: ``max H``, unless the widest
    particles are few (H above the 95th percentile by more than a quarter),
    in which case the 95th percentile; the wider ones then scan stencils of
    their own. (One cell size for all would make every particle test
    ``(max H / H)^dim`` times too many candidates, e.g. around a blast's
    rarefied core.)"""
    H_max = float(H.max())
    H_q = float(np.partition(H, int(0.95 * (H.size - 1)))[int(0.95 * (H.size - 1))])
    return H_max if H_max <= 1.25 * H_q else H_q


def sort_order(x, lo, hi, cell_size):
    r"""Permutation that orders particles cell by cell, for re-sorting particle
    arrays in memory (``x[order]``, ``m[order]``, ...) so that neighbours sit
    close together (better cache use; Domínguez et al. 2011, §3).

    Cells of width ≥ ``cell_size`` (> 0) on the bounding box of ``[lo, hi]``
    and the particles, numbered with x fastest; stable counting sort, O(N),
    so particles of one cell keep their relative order.
    """
    x = positions(x)
    n, dim = x.shape
    lo, hi = ordered_box(lo, hi, dim)
    try:
        cs = float(cell_size)
    except (TypeError, ValueError):
        raise InputError(f"cell_size must be a finite number > 0; got {cell_size!r}.") from None
    if not (math.isfinite(cs) and cs > 0):
        raise InputError(f"cell_size must be a finite number > 0; got {cell_size!r}.")
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    origin, width, ncell, per3, _ = cell_grid(x, lo, hi, np.zeros(dim, bool), cs)
    cid = cell_ids(x, origin[:dim], width[:dim], ncell[:dim], per3[:dim])
    _, order = counting_sort(cid, int(np.prod(ncell)))
    return order


def nearby_maximum(x, values, lo, hi, periodic, distance) -> np.ndarray:
    """For each point, a bound from above on the largest of ``values`` ((n,)
    or (n, k): column by column) over the points within ``distance`` of it
    (minimum image on periodic axes), itself included: the largest over the
    3^dim cells around its own on a grid of cells at least ``distance``
    wide. O(N) with a cell count capped as in :func:`cell_grid`; positions
    may lie outside a non-periodic box."""
    x = positions(x)
    n, dim = x.shape
    values = np.asarray(values, dtype=np.float64)
    if n == 0:
        return values.copy()
    lo, hi = box_corners(lo, hi, dim)
    origin, width, ncell, per, _ = cell_grid(x, lo, hi, periodicity(periodic, dim), float(distance))
    cid = cell_ids(x, origin[:dim], width[:dim], ncell[:dim], per[:dim])
    cells = _cell_maxima(cid, values.reshape(n, -1), int(np.prod(ncell)))
    cells = cells.reshape(tuple(ncell[::-1]) + values.shape[1:])  # (z, y, x): the id is (cz·ny + cy)·nx + cx
    for a in range(dim):
        axis = 2 - a
        if ncell[a] == 1:
            continue
        if per[a]:
            cells = np.maximum(cells, np.maximum(np.roll(cells, 1, axis), np.roll(cells, -1, axis)))
        else:
            grown = cells.copy()
            lower = [slice(None)] * cells.ndim
            upper = [slice(None)] * cells.ndim
            lower[axis], upper[axis] = slice(None, -1), slice(1, None)
            np.maximum(grown[tuple(lower)], cells[tuple(upper)], out=grown[tuple(lower)])
            np.maximum(grown[tuple(upper)], cells[tuple(lower)], out=grown[tuple(upper)])
            cells = grown
    return cells.reshape((-1,) + values.shape[1:])[cid]
