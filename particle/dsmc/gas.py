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

import numpy as np

from compare.checks import InputError


def internal_degrees(gamma: float) -> float:
    """ζ = (5 − 3γ)/(γ − 1) for 1 < γ ≤ 5/3 (a whole number when γ is one
    of a whole number of degrees, to round-off)."""
    if not 1.0 < gamma <= 5.0 / 3.0 + 1e-12:
        raise InputError(f"gamma must be in (1, 5/3] for DSMC (a gas with zeta = (5 - 3 gamma)/(gamma - 1) >= 0 "
                         f"internal degrees of freedom); got {gamma:g}.")
    zeta = max((5.0 - 3.0 * gamma) / (gamma - 1.0), 0.0)
    whole = round(zeta)  # γ = 1.4 gives 2.0000000000000018 in floating point: a diatomic gas's ζ is 2
    return float(whole) if abs(zeta - whole) < 1e-9 else zeta


def equilibrium_particles(rng, n, rho, u, v, p, zeta):
    """Velocities (n, 3) and specific internal energies (n,) of ``n``
    particles drawn from the equilibrium at density ``rho``, flow velocity
    ``(u, v, 0)`` and pressure ``p`` (scalars or arrays of length n)."""
    theta = np.broadcast_to(np.asarray(p, float) / np.asarray(rho, float), (n,))
    scale = np.sqrt(theta)
    vel = rng.standard_normal((n, 3)) * scale[:, None]
    vel[:, 0] += u
    vel[:, 1] += v
    e = rng.gamma(0.5 * zeta, 1.0, n) * theta if zeta > 0 else np.zeros(n)
    return vel, e


def particles_in_cells(rng, lo, spacing, shape, rho, u, v, p, mass, zeta):
    """Particles of mass ``mass`` filling the cells of a uniform grid (origin
    ``lo``, ``spacing`` and ``shape`` per axis) with the cell states ``rho``,
    ``u``, ``v``, ``p`` (arrays of the grid's shape, x fastest in memory as
    (ny, nx) in 2D). Each cell gets ⌊ρV/mass + ξ⌋ particles, ξ uniform in
    [0, 1) (the mean mass is exact), uniformly placed, with equilibrium
    velocities and internal energies. Returns ``(x, v, e)``."""
    dim = len(shape)
    volume = float(np.prod(spacing))
    expected = (np.asarray(rho, float) * volume / mass).reshape(-1)
    count = np.floor(expected + rng.uniform(0.0, 1.0, expected.size)).astype(np.int64)
    cell = np.repeat(np.arange(expected.size), count)
    n = cell.size
    index = np.unravel_index(cell, tuple(reversed(shape)))[::-1]  # (ix, iy)
    x = np.empty((n, dim))
    for a in range(dim):
        x[:, a] = lo[a] + (index[a] + rng.uniform(0.0, 1.0, n)) * spacing[a]
    states = [np.broadcast_to(np.asarray(q, float), tuple(reversed(shape))).reshape(-1)[cell] for q in (rho, u, v, p)]
    vel, e = equilibrium_particles(rng, n, *states, zeta)
    return x, vel, e
