"""Ideal-gas state conversions. A state is a tuple of arrays, one per
variable, laid out ``([y,] x)``: primitive ``W = (rho, u[, v], p)``,
conservative ``U = (rho, rho u[, rho v], E)`` with
``E = p/(gamma-1) + rho |u|^2 / 2`` (Toro 2009, §3.1).

Tuples rather than one stacked array let XLA fuse each kernel into a few
loops without materialising slices of a stacked array.
"""

from __future__ import annotations

import jax.numpy as jnp


def _squared_speed(vel):
    return sum(c * c for c in vel)


def conservative(W, gamma):
    """``U`` from ``W``."""
    rho, vel, p = W[0], W[1:-1], W[-1]
    return (rho, *(rho * c for c in vel), p / (gamma - 1.0) + 0.5 * rho * _squared_speed(vel))


def primitive(U, gamma):
    """``W`` from ``U``."""
    rho, mom, E = U[0], U[1:-1], U[-1]
    inv = 1.0 / rho
    vel = tuple(m * inv for m in mom)
    return (rho, *vel, (gamma - 1.0) * (E - 0.5 * rho * _squared_speed(vel)))


def sound_speed(W, gamma):
    """``c = sqrt(gamma p / rho)``."""
    return jnp.sqrt(gamma * W[-1] / W[0])


def rotated(W, d):
    """``W`` in the frame of direction ``d``: the normal velocity first,
    ``(rho, u_n, u_t..., p)``. Applying it twice restores the order in 2D."""
    if d == 0:
        return W
    vel = list(W[1:-1])
    vel[0], vel[d] = vel[d], vel[0]
    return (W[0], *vel, W[-1])


def normal_flux(W, gamma):
    """Physical flux through a face, from ``W`` in its normal frame
    ``(rho, u_n, u_t..., p)``: ``(ρu_n, ρu_n² + p, ρu_n u_t, u_n(E + p))``."""
    rho, un, vt, p = W[0], W[1], W[2:-1], W[-1]
    m = rho * un
    E = p / (gamma - 1.0) + 0.5 * rho * _squared_speed(W[1:-1])
    return (m, m * un + p, *(m * c for c in vt), un * (E + p))
