"""True binary collisions for DSMC (the non-equilibrium option, SPEC §3.3):
Bird's no-time-counter selection, variable-hard-sphere (VHS) molecules and
Larsen–Borgnakke exchange between translation and rotation (Bird 1994,
"Molecular Gas Dynamics and the Direct Simulation of Gas Flows", §§4.4,
5.4, 11.1; Borgnakke & Larsen 1975, J. Comput. Phys. 18, 405).

Particles have equal masses m and stand for F_N molecules each. VHS: the
total cross-section falls with the relative speed g,

    σ(g) = σ_ref (g / g_ref)^(1 − 2ω),

ω the viscosity–temperature exponent (μ ∝ T^ω; ½ for hard spheres, 0.74
for nitrogen). The reference is the scene's lowest initial density ρ_ref at
θ_ref = p/ρ there (the state that also sets the particles per cell), with
g_ref = 4 √(θ_ref/π) the mean relative speed and mean free path
λ_ref = 1/(√2 n_ref σ_ref); per simulated particle the cross-section is

    F_N σ_ref = m / (√2 ρ_ref λ_ref)

(m/ρ is the volume per particle, so the same formula holds in 1D and 2D with
the cell's length or area for volume).

No-time-counter (Bird 1994 §11.1): a cell of N particles and volume V
tests ⌊½ N (N − 1) (F_N σg)_max Δt / V + ξ⌋ random pairs and accepts each
with probability σ(g) g / (σg)_max, (σg)_max kept per cell and raised when a
pair exceeds it. For Poisson-distributed N, E[N (N − 1)] = N̄², so the mean
collision rate per particle is n σ g as in the gas.

An accepted pair keeps its centre of mass; with ζ > 0 internal degrees each
partner in turn (serial Larsen–Borgnakke), with probability 1/Z_rot, pools
its rotational energy with the pair's relative translational energy
E_t = m g²/4 and takes the fraction x ~ Beta(ζ/2, 5/2 − ω) of it (Bird
1994 eq. 5.46 for VHS); the relative velocity then takes the speed of the
translational energy left, 2 √(E_t/m), in an isotropic direction (VHS
scattering). Each collision conserves momentum and energy to round-off.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.particle.dsmc.cells import record_cell_sums
from partmesh.particle.dsmc.random import gamma, stream, uniform
from partmesh.particle.threads import PRANGE_ONLY


@numba.njit(cache=True, inline="always")
def pair_cross_section_speed(g, sigma, g_ref, omega):
    """σ(g) g of a VHS pair at relative speed ``g`` (module docstring),
    ``sigma`` the per-particle cross-section at ``g_ref``."""
    if g <= 0.0:
        return 0.0
    return sigma * g * (g / g_ref) ** (1.0 - 2.0 * omega)


@numba.njit(cache=True, inline="always")
def _beta(state, a, b):
    """``(state, x)``, x ~ Beta(a, b), as G_a/(G_a + G_b)."""
    state, ga = gamma(state, a)
    state, gb = gamma(state, b)
    return state, ga / (ga + gb)


@numba.njit(cache=True)
def _collide_pair(v, e, i, j, state, zeta, omega, z_rot):
    """Collide particles ``i`` and ``j`` in place (module docstring);
    returns the advanced random state."""
    c0 = 0.5 * (v[i, 0] + v[j, 0])
    c1 = 0.5 * (v[i, 1] + v[j, 1])
    c2 = 0.5 * (v[i, 2] + v[j, 2])
    g0, g1, g2 = v[i, 0] - v[j, 0], v[i, 1] - v[j, 1], v[i, 2] - v[j, 2]
    translational = 0.25 * (g0 * g0 + g1 * g1 + g2 * g2)  # E_t/m
    if zeta > 0.0:
        for k in (i, j):
            state, u = uniform(state)
            if u * z_rot < 1.0:
                pooled = translational + e[k]
                state, x = _beta(state, 0.5 * zeta, 2.5 - omega)
                e[k] = x * pooled
                translational = pooled - e[k]
    speed = 2.0 * math.sqrt(translational)
    state, u = uniform(state)
    cos_t = 2.0 * u - 1.0
    sin_t = math.sqrt(max(1.0 - cos_t * cos_t, 0.0))
    state, u = uniform(state)
    phi = 2.0 * math.pi * u
    h0, h1, h2 = 0.5 * speed * cos_t, 0.5 * speed * sin_t * math.cos(phi), 0.5 * speed * sin_t * math.sin(phi)
    v[i, 0], v[i, 1], v[i, 2] = c0 + h0, c1 + h1, c2 + h2
    v[j, 0], v[j, 1], v[j, 2] = c0 - h0, c1 - h1, c2 - h2
    return state


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def collide(v, e, start, volume, dt, sigma, g_ref, omega, z_rot, zeta, seed, step, sigma_g_max,
            count, momentum, energy):
    """Binary collisions over ``dt`` in every cell (module docstring), in
    place; returns the number of collisions.

    The particles are in cell order: cell c holds ``start[c]:start[c+1]`` in
    the open volume ``volume[c]``; ``sigma`` is F_N σ_ref at ``g_ref``;
    ``sigma_g_max`` (per cell) is (F_N σg)_max, raised in place. Cell c draws
    from the stream ``(seed, step, c)``, so the result does not depend on
    the thread count. Fills, per cell, ``count``, ``momentum`` and
    ``energy``: the sums the collisions conserve."""
    ncell = start.size - 1
    done = np.zeros(ncell, dtype=np.int64)
    for cell in numba.prange(ncell):
        a, b = start[cell], start[cell + 1]
        N = record_cell_sums(v, e, a, b, zeta, cell, count, momentum, energy)[0]
        if N < 2 or volume[cell] <= 0.0:
            continue
        state = stream(seed, step, cell)
        state, xi = uniform(state)
        pairs = int(math.floor(0.5 * N * (N - 1) * sigma_g_max[cell] * dt / volume[cell] + xi))
        for _ in range(pairs):
            state, u = uniform(state)
            i = a + min(int(u * N), N - 1)
            state, u = uniform(state)
            j = a + min(int(u * (N - 1)), N - 2)
            j += 1 if j >= i else 0
            g = math.sqrt((v[i, 0] - v[j, 0]) ** 2 + (v[i, 1] - v[j, 1]) ** 2 + (v[i, 2] - v[j, 2]) ** 2)
            sg = pair_cross_section_speed(g, sigma, g_ref, omega)
            if sg > sigma_g_max[cell]:
                sigma_g_max[cell] = sg
            state, u = uniform(state)
            if u * sigma_g_max[cell] < sg:
                state = _collide_pair(v, e, i, j, state, zeta, omega, z_rot)
                done[cell] += 1
    return done.sum()
