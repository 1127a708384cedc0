"""Equilibrium gas for DSMC: internal degrees of freedom from γ, and
particles drawn from the local equilibrium (SPEC §3.3).

A gas with ζ internal (rotational) degrees of freedom has
γ = (5 + ζ)/(3 + ζ), so ζ = (5 − 3γ)/(γ − 1): ζ = 2 for air (γ = 1.4),
0 for a monatomic gas (γ = 5/3). In equilibrium at temperature θ = kT/m = p/ρ
the three velocity components are normal about the flow velocity with
variance θ and the specific internal energy is Gamma(ζ/2, θ) distributed
(mean ζθ/2), so the specific thermal energy is (3 + ζ)/2 θ = p/((γ − 1)ρ).
"""

from __future__ import annotations

import numba
import numpy as np

from partmesh.cases.errors import InputError
from partmesh.particle.dsmc.random import gamma, normal, stream, uniform
from partmesh.particle.threads import PRANGE_ONLY


def internal_degrees(gamma: float) -> float:
    """ζ = (5 − 3γ)/(γ − 1) for 1 < γ ≤ 5/3 (a whole number when γ is one
    of a whole number of degrees, to round-off)."""
    if not 1.0 < gamma <= 5.0 / 3.0 + 1e-12:
        raise InputError(f"gamma must be in (1, 5/3] for DSMC (a gas with zeta = (5 - 3 gamma)/(gamma - 1) >= 0 "
                         f"internal degrees of freedom); got {gamma:g}.")
    zeta = max((5.0 - 3.0 * gamma) / (gamma - 1.0), 0.0)
    whole = round(zeta)  # γ = 1.4 gives 2.0000000000000018 in floating point: a diatomic gas's ζ is 2
    return float(whole) if abs(zeta - whole) < 1e-9 else zeta


@numba.njit(cache=True, inline="always")
def _count(state, expected):
    """``(state, ⌊expected + ξ⌋)``, ξ uniform: an integer with mean ``expected``."""
    state, xi = uniform(state)
    return state, int(np.floor(expected + xi))


@numba.njit(cache=True, error_model="numpy")
def _fill_cell(c, lo, spacing, shape, rho, u, v, w, p, zeta, seed, step, key0, first, x, vel, e):
    """The particles ``first[c]:first[c + 1]`` of cell ``c`` of :func:`particles_in_cells`."""
    dim = lo.size
    state = _count(stream(seed, step, key0 + c), 0.0)[0]
    corner = np.empty(dim)
    stride = 1
    for a in range(dim):
        corner[a] = lo[a] + ((c // stride) % shape[a]) * spacing[a]
        stride *= shape[a]
    scale = np.sqrt(p[c] / rho[c])
    for k in range(first[c], first[c + 1]):
        for a in range(dim):
            state, xi = uniform(state)
            x[k, a] = corner[a] + xi * spacing[a]
        state, z0 = normal(state)
        state, z1 = normal(state)
        state, z2 = normal(state)
        vel[k, 0] = u[c] + scale * z0
        vel[k, 1] = v[c] + scale * z1
        vel[k, 2] = w[c] + scale * z2
        if zeta > 0.0:
            state, g = gamma(state, 0.5 * zeta)
            e[k] = scale * scale * g


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def particles_in_cells(lo, spacing, shape, rho, u, v, w, p, mass, zeta, seed, step, key0):
    """``(x, v, e)``: particles of mass ``mass`` filling the cells of a uniform
    grid (origin ``lo``, ``spacing`` and int64 ``shape`` per axis, dim = 1,
    2 or 3) with the states ``rho``, ``u``, ``v``, ``w``, ``p`` (flat arrays, x
    fastest). Cell c gets ⌊ρV/mass + ξ⌋ particles (the mean mass is exact),
    uniformly placed, with equilibrium velocities (normal about (u, v, w),
    variance θ = p/ρ per component) and internal energies (θ Gamma(ζ/2)).
    Cell c draws from the stream ``(seed, step, key0 + c)``: the result does
    not depend on the thread count."""
    dim = lo.size
    ncell = rho.size
    volume = 1.0
    for a in range(dim):
        volume *= spacing[a]
    first = np.zeros(ncell + 1, dtype=np.int64)
    for c in numba.prange(ncell):
        first[c + 1] = _count(stream(seed, step, key0 + c), rho[c] * volume / mass)[1]
    for c in range(ncell):
        first[c + 1] += first[c]
    n = first[ncell]
    x = np.empty((n, dim))
    vel = np.empty((n, 3))
    e = np.zeros(n)
    for c in numba.prange(ncell):
        _fill_cell(np.int64(c), lo, spacing, shape, rho, u, v, w, p, zeta, seed, step, key0, first, x, vel, e)
    return x, vel, e
