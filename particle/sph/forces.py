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

Also returned: ∇·v and |∇×v| (2D) per particle, ``-(1/(Ω_i ρ_i)) Σ_j m_j v_ij·∇_i W(H_i)``
and its curl analogue, the largest signal speed a particle sees (for
the time step and the switches), and the Laplacian of u (Brookshaw 1985),
``∇²u_i = 2 Σ_j (m_j/ρ_j) (u_i − u_j) (∂W(r_ij, H_i)/∂r)/r_ij``, for the
conduction switch.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from particle.kernels import kernel_dwdr
from particle.neighbours import separation


@numba.njit(parallel=True, cache=True)
def rates(x, box, half, v, m, u, rho, p, c, omega, H, alpha, alpha_u, offsets, index, kind, dim, n):
    """``(dvdt, dudt, div_v, curl_v, vsig_max, lap_u)`` for the first ``n``
    particles (the fluid; ghosts after them only serve as neighbours) at
    positions ``x`` (``box``, ``half``: see :func:`particle.neighbours.periods`)."""
    dvdt = np.zeros((n, dim))
    dudt = np.zeros(n)
    div_v = np.zeros(n)
    curl_v = np.zeros(n)
    vsig_max = np.zeros(n)
    lap_u = np.zeros(n)
    for i in numba.prange(n):
        pi_term = p[i] / (omega[i] * rho[i] * rho[i])
        acc = np.zeros(dim)
        du = 0.0
        div = 0.0
        curl = 0.0
        lap = 0.0
        vsig_i = c[i]
        for k in range(offsets[i], offsets[i + 1]):
            j = index[k]
            d0, d1, _, rij = separation(x, i, j, box, half)
            if rij <= 0.0:
                continue
            Fi = kernel_dwdr(kind, rij, H[i], dim) if rij < H[i] else 0.0
            Fj = kernel_dwdr(kind, rij, H[j], dim) if rij < H[j] else 0.0
            if Fi == 0.0 and Fj == 0.0:
                continue
            pj_term = p[j] / (omega[j] * rho[j] * rho[j])
            ex0 = d0 / rij
            ex1 = d1 / rij
            dv0 = v[i, 0] - v[j, 0]
            dv1 = v[i, 1] - v[j, 1] if dim > 1 else 0.0
            w = dv0 * ex0 + dv1 * ex1  # v_ij · x̂_ij
            Fbar = 0.5 * (Fi + Fj)
            rho_bar = 0.5 * (rho[i] + rho[j])
            # pressure force (grad-h variational form)
            f = m[j] * (pi_term * Fi + pj_term * Fj)
            # artificial viscosity
            alpha_ij = 0.5 * (alpha[i] + alpha[j])
            vsig = 0.5 * (c[i] + c[j] - 2.0 * alpha_ij * w) if w < 0.0 else 0.5 * (c[i] + c[j])
            if vsig > vsig_i:
                vsig_i = vsig
            if w < 0.0:
                visc = -alpha_ij * vsig * w / rho_bar
                f += m[j] * visc * Fbar
                du += 0.5 * m[j] * visc * w * Fbar
            acc[0] -= f * ex0
            if dim > 1:
                acc[1] -= f * ex1
            # compressional heating p/(Ωρ²) Σ m v_ij·∇W(H_i)
            du += pi_term * m[j] * w * Fi
            # artificial conduction
            vsig_u = math.sqrt(abs(p[i] - p[j]) / rho_bar)
            alpha_u_ij = 0.5 * (alpha_u[i] + alpha_u[j])
            du += m[j] * alpha_u_ij * vsig_u * (u[i] - u[j]) / rho_bar * Fbar
            # velocity divergence and curl with the particle's own kernel
            div -= m[j] * w * Fi
            lap += 2.0 * m[j] / rho[j] * (u[i] - u[j]) * Fi / rij
            if dim > 1:
                curl += m[j] * (dv0 * ex1 - dv1 * ex0) * Fi
        for d in range(dim):
            dvdt[i, d] = acc[d]
        dudt[i] = du
        div_v[i] = div / (omega[i] * rho[i])
        curl_v[i] = abs(curl) / (omega[i] * rho[i])
        vsig_max[i] = vsig_i
        lap_u[i] = lap
    return dvdt, dudt, div_v, curl_v, vsig_max, lap_u
