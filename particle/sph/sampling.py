"""Shepard (kernel-normalised) interpolation of a particle field at a few
points, for probe series sampled many times per run:

    f(x_p) = Σ_j f_j V_j W(|x_p − x_j|, H_j) / Σ_j V_j W(|x_p − x_j|, H_j),   V_j = m_j/ρ_j.

A direct sum over the particles, parallel over particles with per-thread
partial sums: O(N · points), cheaper than building a tree for a handful of
points. (Whole output grids go through :func:`compare.deposit.shepard`.)
"""

from __future__ import annotations

import math

import numba
import numpy as np

from particle.kernels import kernel_w


@numba.njit(parallel=True, cache=True)
def shepard_at_points(points, x, values, volumes, H, kind, dim, n_chunks):
    """``values`` interpolated at ``points`` (n_points, dim), summing over
    ``n_chunks`` blocks of particles in parallel; NaN where no particle's
    support reaches a point."""
    n_points, n = points.shape[0], x.shape[0]
    num = np.zeros((n_chunks, n_points))
    den = np.zeros((n_chunks, n_points))
    chunk = (n + n_chunks - 1) // n_chunks
    for c in numba.prange(n_chunks):
        for j in range(c * chunk, min(n, (c + 1) * chunk)):
            for k in range(n_points):
                r2 = 0.0
                for d in range(dim):
                    diff = points[k, d] - x[j, d]
                    r2 += diff * diff
                r = math.sqrt(r2)
                if r < H[j]:
                    w = volumes[j] * kernel_w(kind, r, H[j], dim)
                    num[c, k] += values[j] * w
                    den[c, k] += w
    out = np.empty(n_points)
    for k in range(n_points):
        total = den[:, k].sum()
        out[k] = num[:, k].sum() / total if total > 0.0 else np.nan
    return out
