"""Shepard (kernel-normalised) interpolation of a particle field at a few
points, for probe series sampled many times per run:

    f(x_p) = Σ_j f_j V_j W(|x_p − x_j|, H_j) / Σ_j V_j W(|x_p − x_j|, H_j),   V_j = m_j/ρ_j.

A direct sum over the particles, parallel over particles with per-thread
partial sums: O(N · points), cheaper than building a tree for a handful of
points, and on the cell centres of a uniform grid in 1D, 2D or 3D (:func:`on_grid`), sorted into the
grid's lines so that each cell sums only the particles whose supports reach it.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.particle.cell_grid import counting_sort
from partmesh.particle.kernels import kernel_w
from partmesh.particle.threads import PRANGE_ONLY


@numba.njit(cache=True, error_model="numpy")
def _add_chunk_sums(first, end, points, x, values, volumes, H, kind, dim, num, den):
    """Adds to ``num`` (k, n_points) and ``den`` (n_points,) the kernel sums of
    :func:`kernel_sums_at_points` over the particles ``first:end``."""
    for j in range(first, end):
        for p in range(points.shape[0]):
            r2 = 0.0
            for d in range(dim):
                diff = points[p, d] - x[j, d]
                r2 += diff * diff
            r = math.sqrt(r2)
            if r < H[j]:
                w = volumes[j] * kernel_w(kind, r, H[j], dim)
                den[p] += w
                for f in range(values.shape[0]):
                    num[f, p] += values[f, j] * w


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def kernel_sums_at_points(points, x, values, volumes, H, kind, dim, n_chunks):
    """``(Σ_j f_j V_j W_pj, Σ_j V_j W_pj)`` at ``points`` (n_points, dim) for
    the ``values`` f (k, n): (k, n_points) and (n_points,), summing over
    ``n_chunks`` blocks of particles in parallel."""
    n_points, n, k = points.shape[0], x.shape[0], values.shape[0]
    num = np.zeros((n_chunks, k, n_points))
    den = np.zeros((n_chunks, n_points))
    chunk = (n + n_chunks - 1) // n_chunks
    for c in numba.prange(n_chunks):
        _add_chunk_sums(c * chunk, min(n, (c + 1) * chunk), points, x, values, volumes, H, kind, dim, num[c], den[c])
    # the chunks added in their order, as num.sum(axis=0) would (whose 3D form compiles for seconds)
    for c in range(1, n_chunks):
        for p in range(n_points):
            den[0, p] += den[c, p]
            for f in range(k):
                num[0, f, p] += num[c, f, p]
    return num[0], den[0]


def shepard_at_points(points, x, values, volumes, H, kind, dim, n_chunks):
    """``values`` (n,) interpolated at ``points`` (n_points, dim); NaN where
    no particle's support reaches a point."""
    num, den = kernel_sums_at_points(points, x, values.reshape(1, -1), volumes, H, kind, dim, n_chunks)
    return _shepard_ratio(num[0], den, 0.0)


def _shepard_ratio(num, den, min_support):
    """``num / den`` where the kernel sum ``den`` is above zero and at least
    ``min_support``; NaN elsewhere."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where((den > 0.0) & (den >= min_support), num / den, np.nan)


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


@numba.njit(cache=True, inline="always")
def _bucket(c, n, periodic):
    """Row (or plane) ``c`` of ``n`` wrapped on a periodic axis; −1 where it lies off a non-periodic one."""
    if periodic:
        return c % n
    return c if 0 <= c < n else -1


@numba.njit(cache=True, error_model="numpy")
def _add_line_sums(s, r, x, y, z, values, volumes, H, x0, dx, nx, y0, dy, ny, z0, dz, nz, periodic, kind, dim,
                   reach_y, reach_z, span_y, span_z, start, order, num, den):
    """Adds to ``num`` and ``den`` of :func:`kernel_sums_on_grid` the sums of
    line (plane ``s``, row ``r``) over the particles of the lines within reach."""
    Lx, Ly, Lz = nx * dx, ny * dy, nz * dz
    periodic_x, periodic_y, periodic_z = periodic[0], periodic[1], periodic[2]
    k = values.shape[0]
    zs, yr = z0 + s * dz, y0 + r * dy
    for ss in range(s - reach_z, s - reach_z + span_z):
        plane = _bucket(ss, nz, periodic_z)
        if plane < 0:
            continue
        for rr in range(r - reach_y, r - reach_y + span_y):
            row = _bucket(rr, ny, periodic_y)
            if row < 0:
                continue
            bucket = plane * ny + row
            for t in range(start[bucket], start[bucket + 1]):
                j = order[t]
                ey = yr - y[j]
                if periodic_y:
                    ey -= Ly * math.floor(ey / Ly + 0.5)
                ez = zs - z[j]
                if periodic_z:
                    ez -= Lz * math.floor(ez / Lz + 0.5)
                across = ey * ey + ez * ez
                if across >= H[j] * H[j]:
                    continue
                half_chord = math.sqrt(H[j] * H[j] - across)
                xj = _wrapped(x[j], x0, dx, Lx) if periodic_x else x[j]
                i_lo = int(math.ceil((xj - half_chord - x0) / dx))
                i_hi = int(math.floor((xj + half_chord - x0) / dx))
                if not periodic_x:
                    i_lo, i_hi = max(i_lo, 0), min(i_hi, nx - 1)
                for i in range(i_lo, i_hi + 1):
                    ex = x0 + i * dx - xj
                    dist = math.sqrt(ex * ex + across)
                    if dist < H[j]:
                        w = volumes[j] * kernel_w(kind, dist, H[j], dim)
                        c = i % nx if periodic_x else i
                        den[s, r, c] += w
                        for f in range(k):
                            num[f, s, r, c] += w * values[f, j]


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def kernel_sums_on_grid(x, y, z, values, volumes, H, x0, dx, nx, y0, dy, ny, z0, dz, nz, periodic, kind, dim):
    """``(Σ_j f_j V_j W, Σ_j V_j W)`` at the centres ``(x0 + i dx, y0 + r dy, z0 + s dz)``
    of a uniform ``nz × ny × nx`` grid for the ``values`` f (k, n): (k, nz, ny, nx)
    and (nz, ny, nx). 2D: ``z`` zeros, ``nz = 1``; 1D: ``y`` zeros too, ``ny = 1``.
    ``periodic`` holds three flags (x, y, z); on a periodic axis the box is the
    grid's extent (n·spacing) and every support must be below half of it.
    The particles are sorted into the grid's lines along x (a plane and a row
    each); each line sums the particles of the lines its supports can reach,
    line by line, so threads never share a cell and the sums do not depend on
    the thread count."""
    n, k = x.size, values.shape[0]
    Ly, Lz = ny * dy, nz * dz
    periodic_y, periodic_z = periodic[1], periodic[2]
    H_max = 0.0
    for j in range(n):
        H_max = max(H_max, H[j])
    reach_y = int(math.ceil(H_max / dy)) + 1 if dim > 1 else 0
    reach_z = int(math.ceil(H_max / dz)) + 1 if dim > 2 else 0
    # the lines within reach, each once on a periodic axis
    span_y = min(2 * reach_y + 1, ny) if periodic_y else 2 * reach_y + 1
    span_z = min(2 * reach_z + 1, nz) if periodic_z else 2 * reach_z + 1
    # line l = s·ny + r holds its particles in their input order: order[start[l]:start[l + 1]]
    line = _rows_of(z, z0, dz, nz, periodic_z, Lz)
    row = _rows_of(y, y0, dy, ny, periodic_y, Ly)
    for j in range(n):
        line[j] = line[j] * ny + row[j]
    start, order = counting_sort(line, nz * ny)
    num = np.zeros((k, nz, ny, nx))
    den = np.zeros((nz, ny, nx))
    for sr in numba.prange(nz * ny):
        _add_line_sums(sr // ny, sr % ny, x, y, z, values, volumes, H, x0, dx, nx, y0, dy, ny, z0, dz, nz,
                       periodic, kind, dim, reach_y, reach_z, span_y, span_z, start, order, num, den)
    return num, den


def shepard_on_grid(x, y, z, values, volumes, H, x0, dx, nx, y0, dy, ny, z0, dz, nz, periodic, kind, dim,
                    min_support):
    """``values`` (k, n) interpolated at the grid centres of
    :func:`kernel_sums_on_grid`: (k, nz, ny, nx), NaN where the kernel sum
    Σ_j V_j W is zero or below ``min_support``."""
    num, den = kernel_sums_on_grid(x, y, z, values, volumes, H, x0, dx, nx, y0, dy, ny, z0, dz, nz, periodic,
                                   kind, dim)
    return _shepard_ratio(num, den, min_support)


def on_grid(x, values, volumes, H, axes, periodic, kind, min_support, lengths=None) -> np.ndarray:
    """Shepard interpolation of ``values`` (k, n) of particles at ``x`` (n, dim)
    on the uniform grid with cell-centre ``axes`` (x[, y[, z]]): the schema
    layout (k, [z, [y,]] x), NaN where the kernel sum is below ``min_support``
    (:func:`shepard_on_grid`). ``periodic``: one flag per axis; ``lengths``:
    the grid's extent per axis, which sets the spacing (and period) of an
    axis of one centre (without it, 1 m)."""
    dim = x.shape[1]
    pos = [np.ascontiguousarray(x[:, a]) if a < dim else np.zeros(x.shape[0]) for a in range(3)]
    grid = []
    for a in range(3):
        c = np.asarray(axes[a], float) if a < dim else np.zeros(1)
        single = float(lengths[a]) if lengths is not None and a < dim else 1.0
        grid += [float(c[0]), float(c[1] - c[0]) if c.size > 1 else single, c.size]
    flags = np.array([bool(periodic[a]) if a < dim else False for a in range(3)])
    out = shepard_on_grid(*pos, np.ascontiguousarray(values), volumes, H, *grid, flags, kind, dim, min_support)
    return out.reshape(out.shape[:1] + out.shape[4 - dim:])
