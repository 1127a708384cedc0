"""Shepard (kernel-normalised) interpolation of a particle field at a few
points, for probe series sampled many times per run:

    f(x_p) = Σ_j f_j V_j W(|x_p − x_j|, H_j) / Σ_j V_j W(|x_p − x_j|, H_j),   V_j = m_j/ρ_j.

A direct sum over the particles, parallel over particles with per-thread
partial sums: O(N · points), cheaper than building a tree for a handful of
points. (Whole output grids go through :func:`partmesh.compare.deposit.shepard`.)
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.particle.cell_grid import counting_sort
from partmesh.particle.kernels import kernel_w


@numba.njit(parallel=True, cache=True)
def kernel_sums_at_points(points, x, values, volumes, H, kind, dim, n_chunks):
    """``(Σ_j f_j V_j W_pj, Σ_j V_j W_pj)`` at ``points`` (n_points, dim) for
    the ``values`` f (k, n): (k, n_points) and (n_points,), summing over
    ``n_chunks`` blocks of particles in parallel."""
    n_points, n, k = points.shape[0], x.shape[0], values.shape[0]
    num = np.zeros((n_chunks, k, n_points))
    den = np.zeros((n_chunks, n_points))
    chunk = (n + n_chunks - 1) // n_chunks
    for c in numba.prange(n_chunks):
        for j in range(c * chunk, min(n, (c + 1) * chunk)):
            for p in range(n_points):
                r2 = 0.0
                for d in range(dim):
                    diff = points[p, d] - x[j, d]
                    r2 += diff * diff
                r = math.sqrt(r2)
                if r < H[j]:
                    w = volumes[j] * kernel_w(kind, r, H[j], dim)
                    den[c, p] += w
                    for f in range(k):
                        num[c, f, p] += values[f, j] * w
    return num.sum(axis=0), den.sum(axis=0)


@numba.njit(cache=True)
def shepard_at_points(points, x, values, volumes, H, kind, dim, n_chunks):
    """``values`` (n,) interpolated at ``points`` (n_points, dim); NaN where
    no particle's support reaches a point."""
    num, den = kernel_sums_at_points(points, x, values.reshape(1, -1), volumes, H, kind, dim, n_chunks)
    out = np.empty(den.size)
    for p in range(den.size):
        out[p] = num[0, p] / den[p] if den[p] > 0.0 else np.nan
    return out


@numba.njit(cache=True, inline="always")
def _wrapped(v, c0, spacing, length):
    """Coordinate ``v`` moved by whole periods ``length`` into the box of a
    periodic axis whose first cell centre is ``c0``: [c0 − spacing/2, c0 − spacing/2 + length)."""
    return v - length * math.floor((v - c0 + 0.5 * spacing) / length)


@numba.njit(cache=True)
def _rows_of(y, y0, dy, ny, periodic, length):
    """Grid row of every particle (clipped into [0, ny) off a periodic axis)."""
    row = np.empty(y.size, dtype=np.int64)
    for j in range(y.size):
        yj = _wrapped(y[j], y0, dy, length) if periodic else y[j]
        row[j] = min(max(int(math.floor((yj - y0) / dy + 0.5)), 0), ny - 1)
    return row


@numba.njit(parallel=True, cache=True)
def kernel_sums_on_grid(x, y, values, volumes, H, x0, dx, nx, y0, dy, ny, periodic_x, periodic_y, kind, dim):
    """``(Σ_j f_j V_j W, Σ_j V_j W)`` at the centres ``(x0 + i dx, y0 + r dy)``
    of a uniform ``ny × nx`` grid for the ``values`` f (k, n): (k, ny, nx)
    and (ny, nx). 1D: ``y`` zeros, ``ny = 1``. On a periodic axis the box
    is the grid's extent (n·spacing) and every support must be below half
    of it. Each grid row sums the particles of the rows its supports can
    reach, row by row, so threads never share a cell and the sums do not
    depend on the thread count."""
    n, k = x.size, values.shape[0]
    Lx, Ly = nx * dx, ny * dy
    H_max = H.max() if n else 0.0
    reach = int(math.ceil(H_max / dy)) + 1 if dim > 1 else 0
    if periodic_y:
        reach = min(reach, (ny - 1) // 2)
    # row r's particles, in their input order: order[start[r]:start[r + 1]]
    start, order = counting_sort(_rows_of(y, y0, dy, ny, periodic_y, Ly), ny)
    num = np.zeros((k, ny, nx))
    den = np.zeros((ny, nx))
    for r in numba.prange(ny):
        yr = y0 + r * dy
        for rr in range(r - reach, r + reach + 1):
            if periodic_y:
                bucket = rr % ny
            elif rr < 0 or rr >= ny:
                continue
            else:
                bucket = rr
            for t in range(start[bucket], start[bucket + 1]):
                j = order[t]
                ey = yr - y[j]
                if periodic_y:
                    ey -= Ly * math.floor(ey / Ly + 0.5)
                if abs(ey) >= H[j]:
                    continue
                half_chord = math.sqrt(H[j] * H[j] - ey * ey)
                xj = _wrapped(x[j], x0, dx, Lx) if periodic_x else x[j]
                i_lo = int(math.ceil((xj - half_chord - x0) / dx))
                i_hi = int(math.floor((xj + half_chord - x0) / dx))
                if not periodic_x:
                    i_lo, i_hi = max(i_lo, 0), min(i_hi, nx - 1)
                for i in range(i_lo, i_hi + 1):
                    ex = x0 + i * dx - xj
                    dist = math.sqrt(ex * ex + ey * ey)
                    if dist < H[j]:
                        w = volumes[j] * kernel_w(kind, dist, H[j], dim)
                        c = i % nx if periodic_x else i
                        den[r, c] += w
                        for f in range(k):
                            num[f, r, c] += w * values[f, j]
    return num, den


@numba.njit(parallel=True, cache=True)
def shepard_on_grid(x, y, values, volumes, H, x0, dx, nx, y0, dy, ny, periodic_x, periodic_y, kind, dim,
                    min_support):
    """``values`` (k, n) interpolated at the grid centres of
    :func:`kernel_sums_on_grid`: (k, ny, nx), NaN where the kernel sum
    Σ_j V_j W is zero or below ``min_support``."""
    k = values.shape[0]
    num, den = kernel_sums_on_grid(x, y, values, volumes, H, x0, dx, nx, y0, dy, ny, periodic_x, periodic_y,
                                   kind, dim)
    out = np.empty((k, ny, nx))
    for r in numba.prange(ny):
        for i in range(nx):
            ok = den[r, i] > 0.0 and den[r, i] >= min_support
            for f in range(k):
                out[f, r, i] = num[f, r, i] / den[r, i] if ok else np.nan
    return out
