"""Switches for the artificial viscosity (Cullen & Dehnen 2010, MNRAS 408,
669) and the artificial conduction (Price 2008, J. Comput. Phys. 227, 10040,
indicator h|∇²u|/√u), both relaxed the same way.

Per particle, with h = H/2 and the signal speed v_sig the particle sees:

    A_i = ξ_i max(−d(∇·v)_i/dt, 0),    ξ_i = (∇·v)² / ((∇·v)² + |∇×v|²)
    α_loc,i = α_max h² A_i / (v_sig² + h² A_i)
    α_i ← α_loc,i                                   if α_i < α_loc,i
    α_i ← α_loc,i + (α_i − α_loc,i) exp(−Δt/τ_i)     else, τ_i = h/(0.1 v_sig)

so the viscosity switches on ahead of a shock (the divergence grows more
negative) and decays behind it, while shear flow (curl ≫ divergence) is
left inviscid. The conduction coefficient follows the same rule with

    α^u_loc,i = α^u_max h|∇²u|_i / (h|∇²u|_i + √u_i),

large where the internal energy has a kink (a contact discontinuity, the
wall-heating spike of Noh's problem) and small in smooth flow.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.particle.threads import PRANGE_ONLY


@numba.njit(cache=True, inline="always")
def _relaxed(alpha, a_loc, tau, dt, alpha_min):
    """α ← α_loc if α < α_loc, else α_loc + (α − α_loc) e^(−Δt/τ); at least α_min."""
    a = a_loc if alpha < a_loc else a_loc + (alpha - a_loc) * math.exp(-dt / tau)
    return max(a, alpha_min)


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def cullen_dehnen(alpha, div_v, div_v_old, curl_v, vsig, H, dt, alpha_max, alpha_min):
    """The updated viscosity coefficients (a new array)."""
    n = alpha.shape[0]
    out = np.empty(n)
    for i in numba.prange(n):
        h = 0.5 * H[i]
        ddiv = (div_v[i] - div_v_old[i]) / dt
        d2 = div_v[i] * div_v[i]
        xi = d2 / (d2 + curl_v[i] * curl_v[i] + 1e-300)
        A = xi * max(-ddiv, 0.0)
        a_loc = alpha_max * h * h * A / (vsig[i] * vsig[i] + h * h * A)
        out[i] = _relaxed(alpha[i], a_loc, h / (0.1 * vsig[i]), dt, alpha_min)
    return out


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def conduction_switch(alpha_u, lap_u, u, vsig, H, dt, alpha_u_max, alpha_u_min):
    """The updated conduction coefficients (a new array)."""
    n = alpha_u.shape[0]
    out = np.empty(n)
    for i in numba.prange(n):
        h = 0.5 * H[i]
        S = h * abs(lap_u[i])
        a_loc = alpha_u_max * S / (S + math.sqrt(u[i]))
        out[i] = _relaxed(alpha_u[i], a_loc, h / (0.1 * vsig[i]), dt, alpha_u_min)
    return out
