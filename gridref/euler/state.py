"""State conversions. A state is a tuple of arrays, one per
variable, laid out ``([y,] x)``: primitive ``W = (rho, u[, v], p)``,
conservative ``U = (rho, rho u[, rho v], E)`` with
``E = p/(gamma-1) + rho |u|^2 / 2`` (Toro 2009, §3.1) for an ideal gas of
``gas = gamma``. For detonation products and air (``gas`` a
:class:`~partmesh.gridref.euler.mixture.Mixture`) the cell's scalars follow
the velocities in both, ``W = (rho, u[, v], rhoY, rhoYλ, α, p)`` and
``U = (rho, rho u[, rho v], rhoY, rhoYλ, α, E)``, and the mixture's
equation of state relates ``E − rho |u|²/2`` to ``p``.

Tuples rather than one stacked array let XLA fuse each kernel into a few
loops without materialising slices of a stacked array.
"""

from __future__ import annotations

import jax.numpy as jnp


def _squared_speed(vel):
    return sum(c * c for c in vel)


def scalar_count(gas) -> int:
    """How many scalars a cell of ``gas`` carries after its velocities (0 for an ideal gas)."""
    return getattr(gas, "scalars", 0)


def first_scalar(W, gas) -> int:
    """The index of the first scalar in a state tuple ``W`` or ``U`` of ``gas`` (past its velocities)."""
    return len(W) - 1 - scalar_count(gas)


def density_scalars(W, gas) -> range:
    """The indices in ``W`` of the scalars advected like a density (a mixture's partial densities)."""
    first = first_scalar(W, gas)
    return range(first, first + getattr(gas, "densities", 0))


def parts(W, gas):
    """``(rho, velocities, scalars, last)`` of a state tuple ``W`` or ``U`` of ``gas``."""
    n = first_scalar(W, gas)
    return W[0], W[1:n], W[n:-1], W[-1]


def internal_energy(rho, scalars, p, gas):
    """ρe at pressure ``p``: ``p/(γ−1)`` for an ideal gas."""
    return p / (gas - 1.0) if not scalar_count(gas) else gas.internal_energy(rho, scalars, p, jnp)


def pressure(rho, scalars, rho_e, gas):
    """p from the internal energy per volume ``rho_e``: ``(γ−1) ρe`` for an ideal gas."""
    return (gas - 1.0) * rho_e if not scalar_count(gas) else gas.pressure(rho, scalars, rho_e, jnp)


def stiffness(W, gas):
    """``ρc²`` of the primitive state ``W``: ``γ p`` for an ideal gas."""
    if not scalar_count(gas):
        return gas * W[-1]
    rho, _, scalars, p = parts(W, gas)
    return gas.stiffness(rho, scalars, p, jnp)


def conservative(W, gas):
    """``U`` from ``W``."""
    rho, vel, scalars, p = parts(W, gas)
    return (rho, *(rho * c for c in vel), *scalars, internal_energy(rho, scalars, p, gas)
            + 0.5 * rho * _squared_speed(vel))


def primitive(U, gas):
    """``W`` from ``U``."""
    rho, mom, scalars, E = parts(U, gas)
    inv = 1.0 / rho
    vel = tuple(m * inv for m in mom)
    return (rho, *vel, *scalars, pressure(rho, scalars, E - 0.5 * rho * _squared_speed(vel), gas))


def sound_speed(W, gas):
    """``c = sqrt(gamma p / rho)`` (of a mixture, ``sqrt(ρc²/ρ)``)."""
    if not scalar_count(gas):
        return jnp.sqrt(gas * W[-1] / W[0])
    return jnp.sqrt(stiffness(W, gas) / W[0])


def rotated(W, d):
    """``W`` in the frame of direction ``d``: the normal velocity first,
    ``(rho, u_n, u_t..., p)``. Applying it twice restores the order in 2D."""
    if d == 0:
        return W
    vel = list(W[1:-1])
    vel[0], vel[d] = vel[d], vel[0]
    return (W[0], *vel, W[-1])


def normal_flux(W, gas):
    """Physical flux through a face, from ``W`` in its normal frame
    ``(rho, u_n, u_t..., p)``: ``(ρu_n, ρu_n² + p, ρu_n u_t, u_n(E + p))``;
    a mixture's scalars ``q`` (per volume) carry ``u_n q``."""
    rho, vel, scalars, p = parts(W, gas)
    un, vt = vel[0], vel[1:]
    m = rho * un
    E = internal_energy(rho, scalars, p, gas) + 0.5 * rho * _squared_speed(vel)
    return (m, m * un + p, *(m * c for c in vt), *(un * q for q in scalars), un * (E + p))
