"""Rates of change of gas SPH particles: the variational (grad-h) momentum
and energy equations with artificial viscosity and conduction (Price 2012,
J. Comput. Phys. 231, 759, eqs. 35–36, 101–103; Prasanna Kumar, Patnaik &
Ramamurthi 2018, Phys. Fluids 30, 046105).

    dv_i/dt = −Σ_j m_j [ p_i/(Ω_i ρ_i²) ∇_i W(r_ij, H_i) + p_j/(Ω_j ρ_j²) ∇_i W(r_ij, H_j) ]
              − Σ_j m_j Π_ij ∇̄_i W_ij
    du_i/dt = p_i/(Ω_i ρ_i²) Σ_j m_j v_ij·∇_i W(r_ij, H_i) + ½ Σ_j m_j Π_ij v_ij·∇̄_i W_ij
              + Σ_j m_j α^u_ij v^u_sig (u_i − u_j)/ρ̄_ij  x̂_ij·∇̄_i W_ij

with ∇̄W = ½(∇W(H_i) + ∇W(H_j)), Π_ij = −α_ij v_sig w_ij/ρ̄_ij for
approaching pairs (w_ij = v_ij·x̂_ij < 0), v_sig = ½(c_i + c_j − β w_ij),
β = 2α_ij, α_ij = ½(α_i + α_j), and the conduction signal speed
v^u_sig = sqrt(|p_i − p_j|/ρ̄_ij).

Also returned: ∇·v and |∇×v| per particle, ``-(1/(Ω_i ρ_i)) Σ_j m_j v_ij·∇_i W(H_i)``
and the length of its curl analogue ``(1/(Ω_i ρ_i)) |Σ_j m_j v_ij × ∇_i W(H_i)|`` (in 2D only its z component,
``(v_ij × x̂_ij)_z``, differs from zero; in 1D none does), the largest signal speed a particle
sees (for the time step and the switches), and the Laplacian of u (Brookshaw 1985),
``∇²u_i = 2 Σ_j (m_j/ρ_j) (u_i − u_j) (∂W(r_ij, H_i)/∂r)/r_ij``, for the
conduction switch.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.particle.kernels import SIGMA, shape_derivative
from partmesh.particle.pair_geometry import FASTMATH, separation
from partmesh.particle.threads import PRANGE_ONLY

#: the columns of the per-particle table the pair loop reads (x: 0–2)
_V, _M, _U, _RHO, _P, _C, _ALPHA, _ALPHA_U, _INV_H, _GRAD, _P_TERM, _VOLUME, _FIELDS = (
    3, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17)


@numba.njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def _chunk_rates(Q, c, offsets, index, box, half, kind, dim, n, first, end, out):
    """Adds the pair terms of the rows ``first:end`` to ``out`` (one row per
    particle: a0, a1, a2, du, div, curl_z, lap, vsig[, curl_x, curl_y]) as
    :func:`rates` describes; returns the ordered pairs summed."""
    pairs = 0
    for i in range(first, end):
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        du = 0.0
        div = 0.0
        curl = 0.0
        curl_x = 0.0
        curl_y = 0.0
        lap = 0.0
        vsig_i = c[i]
        inv_Hi, grad_i, p_term_i = Q[i, _INV_H], Q[i, _GRAD], Q[i, _P_TERM]
        for k in range(offsets[i], offsets[i + 1]):
            j = index[k]
            if j < i:
                continue  # evaluated in row j
            d0, d1, d2, r2 = separation(Q, i, j, box, half)
            inv_Hj = Q[j, _INV_H]
            if r2 * min(inv_Hi * inv_Hi, inv_Hj * inv_Hj) >= 1.0 or r2 <= 0.0:
                continue  # beyond both supports (the lists hold a margin)
            rij = math.sqrt(r2)
            qi = rij * inv_Hi
            qj = rij * inv_Hj
            Fi = grad_i * shape_derivative(kind, qi) if qi < 1.0 else 0.0
            Fj = Q[j, _GRAD] * shape_derivative(kind, qj) if qj < 1.0 else 0.0
            inv_r = 1.0 / rij
            ex0 = d0 * inv_r
            ex1 = d1 * inv_r
            ex2 = d2 * inv_r
            dv0 = Q[i, _V] - Q[j, _V]
            dv1 = Q[i, _V + 1] - Q[j, _V + 1]
            dv2 = Q[i, _V + 2] - Q[j, _V + 2]
            w = dv0 * ex0 + dv1 * ex1 + dv2 * ex2  # v_ij · x̂_ij (the same seen from j)
            Fbar = 0.5 * (Fi + Fj)
            inv_rho_bar = 2.0 / (Q[i, _RHO] + Q[j, _RHO])
            # pressure force (grad-h variational form) per unit neighbour mass
            g = p_term_i * Fi + Q[j, _P_TERM] * Fj
            # artificial viscosity
            alpha_ij = 0.5 * (Q[i, _ALPHA] + Q[j, _ALPHA])
            vsig = 0.5 * (Q[i, _C] + Q[j, _C])
            visc = 0.0
            if w < 0.0:
                vsig -= alpha_ij * w
                visc = -alpha_ij * vsig * w * inv_rho_bar * Fbar
                g += visc
            vsig_i = max(vsig_i, vsig)
            # artificial conduction per unit neighbour mass, times (u_i − u_j)
            cond = (0.5 * (Q[i, _ALPHA_U] + Q[j, _ALPHA_U]) * math.sqrt(abs(Q[i, _P] - Q[j, _P]) * inv_rho_bar)
                    * inv_rho_bar * Fbar)
            du_ij = Q[i, _U] - Q[j, _U]
            twist = dv0 * ex1 - dv1 * ex0
            mj = Q[j, _M]
            f = mj * g
            a0 -= f * ex0
            a1 -= f * ex1
            a2 -= f * ex2
            # compressional heating p/(Ωρ²) Σ m v_ij·∇W(H_i), and ∇·v with the particle's own kernel
            mwF = mj * w * Fi
            du += mj * (0.5 * visc * w + cond * du_ij) + p_term_i * mwF
            div -= mwF
            lap += 2.0 * Q[j, _VOLUME] * du_ij * Fi * inv_r
            curl += mj * twist * Fi
            twist_x = 0.0
            twist_y = 0.0
            if dim == 3:  # the other components of v_ij × x̂_ij
                twist_x = dv1 * ex2 - dv2 * ex1
                twist_y = dv2 * ex0 - dv0 * ex2
                curl_x += mj * twist_x * Fi
                curl_y += mj * twist_y * Fi
            pairs += 1
            if j >= n:
                continue  # a ghost or imposed particle: its rates are not needed
            # the same pair seen from j: x̂_ji = −x̂_ij, v_ji·x̂_ji = w
            mi = Q[i, _M]
            f = mi * g
            out[j, 0] += f * ex0
            out[j, 1] += f * ex1
            out[j, 2] += f * ex2
            mwF = mi * w * Fj
            out[j, 3] += mi * (0.5 * visc * w - cond * du_ij) + Q[j, _P_TERM] * mwF
            out[j, 4] -= mwF
            out[j, 5] += mi * twist * Fj
            out[j, 6] -= 2.0 * Q[i, _VOLUME] * du_ij * Fj * inv_r
            out[j, 7] = max(out[j, 7], vsig)
            if dim == 3:
                out[j, 8] += mi * twist_x * Fj
                out[j, 9] += mi * twist_y * Fj
            pairs += 1
        out[i, 0] += a0
        out[i, 1] += a1
        out[i, 2] += a2
        out[i, 3] += du
        out[i, 4] += div
        out[i, 5] += curl
        out[i, 6] += lap
        out[i, 7] = max(out[i, 7], vsig_i)
        if dim == 3:
            out[i, 8] += curl_x
            out[i, 9] += curl_y
    return pairs


@numba.njit(parallel=PRANGE_ONLY, cache=True, fastmath=FASTMATH, error_model="numpy")
def rates(x, box, half, v, m, u, rho, p, c, omega, H, alpha, alpha_u, offsets, index, kind, dim, n, chunks):
    """``(dvdt, dudt, div_v, curl_v, vsig_max, lap_u, interactions)`` for the
    first ``n`` particles (the fluid; ghosts after them only serve as
    neighbours); ``interactions`` counts the ordered pairs (i fluid, j) with
    r_ij < max(H_i, H_j) whose terms were summed.

    ``x`` is (N, 3) (:func:`partmesh.particle.pair_geometry.padded`: zeros beyond
    ``dim``) and ``v`` (N, dim) or (N, 3), ``box``/``half`` as from
    :func:`partmesh.particle.pair_geometry.periods`.
    Each fluid–fluid pair is evaluated once, in the row of its smaller index,
    and its terms are added to both particles (the lists are symmetric: j is
    in i's list exactly when i is in j's). The rows are cut into ``chunks``
    contiguous chunks (one per thread) and every chunk scatters into its own
    accumulators, summed in chunk order at the end: no write races, and the
    result does not change from run to run at a given chunk count. The
    per-particle factors (1/H, σ_d/H^(d+1), p/(Ωρ²), m/ρ) are computed once,
    so a pair costs two kernel-derivative polynomials, two square roots (r
    and the conduction signal speed) and two divisions (1/r and 1/ρ̄); they
    and the state sit in one row per particle (``Q``), so a neighbour's
    values come in two or three cache lines, not one per array (Sedov, 200 704
    particles, 27 passes: 3.2–3.3 s, against 3.6–3.9 s with an array per
    quantity)."""
    N = x.shape[0]
    sigma = SIGMA[kind, dim]
    # every value a pair reads of a particle, side by side: a neighbour costs two or three cache
    # lines instead of one per array
    Q = np.empty((N, _FIELDS))
    for j in numba.prange(N):
        for a in range(3):
            Q[j, a] = x[j, a]
            Q[j, _V + a] = v[j, a] if a < v.shape[1] else 0.0
        Q[j, _M] = m[j]
        Q[j, _U] = u[j]
        Q[j, _RHO] = rho[j]
        Q[j, _P] = p[j]
        Q[j, _C] = c[j]
        Q[j, _ALPHA] = alpha[j]
        Q[j, _ALPHA_U] = alpha_u[j]
        Q[j, _INV_H] = 1.0 / H[j]
        Q[j, _GRAD] = sigma * Q[j, _INV_H] ** (dim + 1)
        Q[j, _P_TERM] = p[j] / (omega[j] * rho[j] * rho[j])
        Q[j, _VOLUME] = m[j] / rho[j]
    nchunk = max(1, min(chunks, n))
    # per chunk and particle: a0, a1, a2, du, div, curl_z, lap, vsig, and in 3D curl_x, curl_y
    acc = np.zeros((nchunk, n, 10 if dim == 3 else 8))
    counted = np.zeros(nchunk, dtype=np.int64)
    for ch in numba.prange(nchunk):
        counted[ch] = _chunk_rates(Q, c, offsets, index, box, half, kind, dim, n, ch * n // nchunk,
                                   (ch + 1) * n // nchunk, acc[ch])
    dvdt = np.empty((n, dim))
    dudt = np.empty(n)
    div_v = np.empty(n)
    curl_v = np.empty(n)
    vsig_max = np.empty(n)
    lap_u = np.empty(n)
    for i in numba.prange(n):
        for q in range(7):
            total = 0.0
            for ch in range(nchunk):
                total += acc[ch, i, q]
            if q < dim:
                dvdt[i, q] = total
            elif q == 3:
                dudt[i] = total
            elif q == 4:
                div_v[i] = total / (omega[i] * rho[i])
            elif q == 5:
                if dim == 3:
                    cx = 0.0
                    cy = 0.0
                    for ch in range(nchunk):
                        cx += acc[ch, i, 8]
                        cy += acc[ch, i, 9]
                    total = math.sqrt(cx * cx + cy * cy + total * total)
                curl_v[i] = abs(total) / (omega[i] * rho[i])
            elif q == 6:
                lap_u[i] = total
        fastest = 0.0
        for ch in range(nchunk):
            fastest = max(fastest, acc[ch, i, 7])
        vsig_max[i] = fastest
    interactions = 0  # (a loop: counted.sum() would compile numpy's sum for this kernel alone)
    for ch in range(nchunk):
        interactions += counted[ch]
    return dvdt, dudt, div_v, curl_v, vsig_max, lap_u, interactions
