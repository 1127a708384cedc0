"""The Cullen & Dehnen (2010, MNRAS 408, 669) artificial-viscosity switch.

Per particle, with h = H/2 and the signal speed v_sig the particle sees:

    A_i = ξ_i max(−d(∇·v)_i/dt, 0),    ξ_i = (∇·v)² / ((∇·v)² + |∇×v|²)
    α_loc,i = α_max h² A_i / (v_sig² + h² A_i)
    α_i ← α_loc,i                                   if α_i < α_loc,i
    α_i ← α_loc,i + (α_i − α_loc,i) exp(−Δt/τ_i)     else, τ_i = h/(0.1 v_sig)

so the viscosity switches on ahead of a shock (the divergence grows more
negative) and decays behind it, while shear flow (curl ≫ divergence) is
left inviscid.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(parallel=True, cache=True)
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
        if alpha[i] < a_loc:
            a = a_loc
        else:
            tau = h / (0.1 * vsig[i])
            a = a_loc + (alpha[i] - a_loc) * math.exp(-dt / tau)
        out[i] = max(a, alpha_min)
    return out
