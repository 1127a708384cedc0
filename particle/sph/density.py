"""Summation density with adaptive smoothing length and the grad-h term
(Springel & Hernquist 2002; Price 2012, J. Comput. Phys. 231, 759, §2.3).

For every particle the support radius ``H_i`` and the density solve, jointly,

    ρ_i = Σ_j m_j W(r_ij, H_i),        H_i = η (m_i/ρ_i)^(1/d),

by Newton–Raphson on f(H) = Σ_j m_j W(r_ij, H) − m_i (η/H)^d with a
bisection fallback, and

    Ω_i = 1 − (∂H_i/∂ρ_i) Σ_j m_j ∂W(r_ij, H_i)/∂H_i,   ∂H/∂ρ = −H/(d ρ).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.particle.kernels import SIGMA, shape, shape_derivative
from partmesh.particle.pair_geometry import separation
from partmesh.particle.threads import PRANGE_ONLY

#: relative tolerance of the H iteration
TOLERANCE = 1e-8
MAX_ITERATIONS = 60


@numba.njit(cache=True)
def _sums(i, H, m, r, neighbour, kind, dim):
    """Σ_j m_j W(r_ij, H) and Σ_j m_j ∂W/∂H over the neighbours of i (self
    included; ``r`` and ``neighbour`` list the others), with the kernel's
    prefactor σ_d/H^d taken out of the sum:
    W = σ_d/H^d f(q), ∂W/∂H = −σ_d/H^(d+1) (d f(q) + q f'(q))."""
    inv = 1.0 / H
    f0 = shape(kind, 0.0)
    sum_f = m[i] * f0
    sum_g = m[i] * dim * f0
    for k in range(r.size):
        if r[k] < H:
            q = r[k] * inv
            fq = shape(kind, q)
            sum_f += m[neighbour[k]] * fq
            sum_g += m[neighbour[k]] * (dim * fq + q * shape_derivative(kind, q))
    scale = SIGMA[kind, dim] * inv ** dim
    return scale * sum_f, -scale * inv * sum_g


_CHUNK = 256


@numba.njit(cache=True, error_model="numpy")
def _chunk_density(first, end, x, box, half, m, H, H_max, offsets, index, kind, dim, eta, scratch,
                   rho_out, H_out, omega, converged):
    """Solves :func:`density_and_support` for the particles ``first:end``,
    each particle's distances in ``scratch``."""
    for i in range(first, end):
        a, b = offsets[i], offsets[i + 1]
        for k in range(a, b):
            scratch[k - a] = math.sqrt(separation(x, i, index[k], box, half)[3])
        r, neighbour = scratch[: b - a], index[a:b]
        h = H[i]
        # the support cannot shrink by more than it may grow within one step: bracket [H²/H_max, H_max]
        lo, hi = H[i] * H[i] / H_max[i], H_max[i]
        ok = False
        for _ in range(MAX_ITERATIONS):
            rho, drho = _sums(i, h, m, r, neighbour, kind, dim)
            target = m[i] * (eta / h) ** dim
            f = rho - target
            # f grows with H: keep a bracket, f > 0 means H is too large
            if f > 0.0:
                hi = min(hi, h)
            else:
                lo = max(lo, h)
            df = drho + dim * target / h
            h_new = h - f / df if df > 0.0 else 0.5 * (lo + hi)
            if abs(h_new - h) <= TOLERANCE * h:
                # h (whose sums these are) solves f = 0 to the tolerance (checked before the
                # bracket: at f = 0 exactly, h itself is a bracket end)
                ok = True
                break
            if not (lo < h_new < hi):
                h_new = 0.5 * (lo + hi)
            h = h_new
        H_out[i] = h
        rho_out[i] = rho
        omega[i] = 1.0 + h / (dim * rho) * drho
        converged[i] = ok


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def density_and_support(x, box, half, m, H, H_max, offsets, index, kind, dim, eta, n):
    """``(rho, H, omega, converged)`` for the first ``n`` particles (the
    fluid; ghosts follow them and only serve as neighbours) at positions
    ``x`` (``box``, ``half``: see :func:`partmesh.particle.pair_geometry.periods`).

    ``x`` is (N, 3) (:func:`partmesh.particle.pair_geometry.padded`). ``H`` is
    the starting guess and ``H_max`` the largest support the neighbour lists
    were built for (the solution is kept below it).
    Distances are computed once per particle into a scratch list shared by
    a chunk of particles, then every iteration reads them.
    """
    rho_out = np.empty(n)
    H_out = np.empty(n)
    omega = np.empty(n)
    converged = np.ones(n, dtype=np.bool_)
    longest = 0
    for i in range(n):
        longest = max(longest, offsets[i + 1] - offsets[i])
    for chunk in numba.prange((n + _CHUNK - 1) // _CHUNK):
        _chunk_density(chunk * _CHUNK, min(n, (chunk + 1) * _CHUNK), x, box, half, m, H, H_max, offsets, index,
                       kind, dim, eta, np.empty(longest), rho_out, H_out, omega, converged)
    return rho_out, H_out, omega, converged
