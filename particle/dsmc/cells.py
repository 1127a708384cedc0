"""DSMC particles sorted into the cells of a uniform grid (SPEC §3.3).

Every step the particles are put in cell order in memory — a stable,
parallel counting sort, O(N) — so that a cell's particles are one contiguous
slice ``start[c]:start[c+1]`` of the arrays: the equilibrium redraw then
reads and writes memory in sequence, and a cell's sums need no gather.

The sort is stable (within a cell, particles keep their previous order) and
its result does not depend on the number of chunks it is split into, so a
run is the same whatever the thread count.
"""

from __future__ import annotations

import numba
import numpy as np

from partmesh.particle.threads import PRANGE_ONLY

#: the weights of unweighted (planar) particles for :func:`sort_into_cells`
UNWEIGHTED = np.empty(0)


def with_room(n: int) -> int:
    """Buffer length for ``n`` particles and a quarter more: room for the
    particles an inflow adds before the next sort."""
    return n + n // 4 + 16


def particle_buffers(n: int, dim: int, weighted: bool) -> tuple:
    """Empty ``(x, v, e, w)`` buffers of :func:`with_room` ``(n)`` particles
    in ``dim`` dimensions; ``w`` is :data:`UNWEIGHTED` unless ``weighted``."""
    capacity = with_room(n)
    return (np.empty((capacity, dim)), np.empty((capacity, 3)), np.empty(capacity),
            np.empty(capacity) if weighted else UNWEIGHTED)


@numba.njit(cache=True, inline="always")
def _cell(x, i, lo, spacing, shape):
    """Linear cell index (x fastest) of particle ``i``, clamped to the grid."""
    c = 0
    stride = 1
    for a in range(x.shape[1]):
        k = int(np.floor((x[i, a] - lo[a]) / spacing[a]))
        k = min(max(k, 0), shape[a] - 1)
        c += k * stride
        stride *= shape[a]
    return c


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def cell_index(x, lo, spacing, shape):
    """Linear cell index (x fastest) of positions ``x`` (n, dim) on the grid
    with origin ``lo``, ``spacing`` and ``shape`` (int64) per axis, clamped
    to the grid."""
    n = x.shape[0]
    cell = np.empty(n, dtype=np.int64)
    for i in numba.prange(n):
        cell[i] = _cell(x, i, lo, spacing, shape)
    return cell


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def sort_into_cells(x, v, e, w, keep, lo, spacing, shape, chunks, xs, vs, es, ws):
    """Copy the particles ``x`` (n, dim), ``v`` (n, 3), ``e`` (n,) and their
    weights ``w`` (n,; empty for unweighted particles, ``ws`` then empty too)
    for which ``keep`` (n,) is true into ``xs``, ``vs``, ``es``, ``ws`` in cell order; returns
    ``start``, cell c holding ``start[c]:start[c+1]``, so ``start[-1]``
    particles were kept. Dropping the particles that left the run here
    saves a compaction pass over every array.

    A counting sort in ``chunks`` contiguous pieces of the particle range:
    each piece counts its particles per cell, an exclusive scan over (cell,
    piece) gives every piece its place in every cell, and each piece copies
    its particles there in their order — the stable sort, whatever
    ``chunks``."""
    n, dim = x.shape
    weighted = w.shape[0] > 0
    ncell = 1
    for a in range(dim):
        ncell *= shape[a]
    size = (n + chunks - 1) // chunks
    cell = np.empty(n, dtype=np.int64)
    place = np.zeros((chunks, ncell), dtype=np.int64)
    for t in numba.prange(chunks):
        for i in range(t * size, min(n, (t + 1) * size)):
            if keep[i]:
                c = _cell(x, i, lo, spacing, shape)
                cell[i] = c
                place[t, c] += 1
    start = np.empty(ncell + 1, dtype=np.int64)
    total = 0
    for c in range(ncell):
        start[c] = total
        for t in range(chunks):
            count = place[t, c]
            place[t, c] = total
            total += count
    start[ncell] = total
    for t in numba.prange(chunks):
        for i in range(t * size, min(n, (t + 1) * size)):
            if not keep[i]:
                continue
            c = cell[i]
            k = place[t, c]
            place[t, c] = k + 1
            for a in range(dim):
                xs[k, a] = x[i, a]
            vs[k, 0] = v[i, 0]
            vs[k, 1] = v[i, 1]
            vs[k, 2] = v[i, 2]
            es[k] = e[i]
            if weighted:
                ws[k] = w[i]
    return start


@numba.njit(cache=True, inline="always")
def weighted_sums(v, e, w, a, b, zeta):
    """``(Σw, Σ w v_x, Σ w v_y, Σ w v_z, Σ w (½|v|² + e))`` of the particles
    ``a:b``; ``w`` empty means weights 1, and the internal energies count
    only if ``zeta`` > 0."""
    weighted = w.shape[0] > 0
    S = p0 = p1 = p2 = total = 0.0
    for i in range(a, b):
        wi = w[i] if weighted else 1.0
        S += wi
        p0 += wi * v[i, 0]
        p1 += wi * v[i, 1]
        p2 += wi * v[i, 2]
        heat = 0.5 * (v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2])
        if zeta > 0.0:
            heat += e[i]
        total += wi * heat
    return S, p0, p1, p2, total


@numba.njit(cache=True, inline="always")
def record_cell_sums(v, e, a, b, zeta, cell, count, momentum, energy):
    """Write N, Σv (three components) and Σ(½|v|² + e) of the particles
    ``a:b`` (cell ``cell``, once sorted) into ``count``, ``momentum`` and
    ``energy``, and return them as ``(N, Σv_x, Σv_y, Σv_z, Σ(½|v|² + e))``;
    the internal energies count only if ``zeta`` > 0."""
    p0 = p1 = p2 = 0.0
    total = 0.0
    for i in range(a, b):
        p0 += v[i, 0]
        p1 += v[i, 1]
        p2 += v[i, 2]
        total += 0.5 * (v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2])
        if zeta > 0.0:
            total += e[i]
    count[cell] = b - a
    momentum[cell, 0], momentum[cell, 1], momentum[cell, 2] = p0, p1, p2
    energy[cell] = total
    return b - a, p0, p1, p2, total
