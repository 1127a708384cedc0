"""The geometry of axisymmetric SPH (García-Senz, Relaño, Cabezón & Bravo
2009, MNRAS 392, 346, §2): the density near the axis and the factors its
equations take from it.

Particles in the r–z plane carry ring masses ``m = 2π r ρ dA``; the 2D
summation with the mirror ghosts across the axis (``x_lo`` reflecting)
gives ``η_i = Σ_j m_j W(r_ij, H_i)``, which for a uniform gas is

    η_i = 2π ρ ∫ |r'| W₁(r' − r_i, H_i) dr' = 2π ρ r̃_i,   r̃ = r + 2 H J(r / H),

``W₁`` the kernel projected onto r (its marginal, normalised to 1) and

    J(ζ) = ∫_ζ^1 (s − ζ) W₁(s) ds     (unit support; J = 0 for ζ ≥ 1),

the share of the kernel's first moment beyond the axis that the ghosts
add. So ``ρ_i = η_i / (2π r̃_i)`` is exact for a uniform gas at any
distance from the axis, where ``η / (2π r)`` would diverge on it. With
``M(ζ) = ∫_ζ^1 W₁(s) ds`` (so ``J' = −M``, ``M(0) = ½``):

    ∂r̃/∂r = 1 − 2 M(ζ)                (0 on the axis),
    Φ = 1 + (H / 2r̃) ∂r̃/∂H = 1 + H (J + ζ M) / r̃,

``Φ`` the factor by which ρ's dependence on H through ``r̃`` scales the
pair terms of the variational equations (1.5 on the axis, 1 beyond one
support). They follow from the Lagrangian ``Σ m (v²/2 − u(ρ))`` with
``ρ = η/(2π r̃)`` and ``H = η_H (m/η)^(1/2)``, ``P = (γ − 1) η u`` (the
pressure times 2π r̃):

    dv_i/dt = −Σ_j m_j [ Φ_i P_i/(Ω_i η_i²) ∇_i W(H_i) + Φ_j P_j/(Ω_j η_j²) ∇_i W(H_j) ]
              + (γ − 1) u_i (∂r̃/∂r)_i / r̃_i  r̂,
    du_i/dt = Φ_i P_i/(Ω_i η_i²) Σ_j m_j v_ij·∇_i W(H_i) − (γ − 1) u_i (∂r̃/∂r)_i v_r,i / r̃_i,

the planar SPH of η and ΦP with the hoop terms, which conserve energy
together; in a uniform gas the Ω of η's summation equals Φ, so the pair
force balances the hoop term at every distance from the axis.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numba
import numpy as np

from partmesh.particle.kernels import SIGMA, shape

#: points of the tables of J and M over ζ in [0, 1]
TABLE_POINTS = 2001


@numba.njit(cache=True)
def _shapes(kind, q):
    """f(q) of kernel ``kind`` at every value of the 1D array ``q`` (0 beyond q = 1)."""
    out = np.zeros(q.size)
    for k in range(q.size):
        if q[k] < 1.0:
            out[k] = shape(kind, q[k])
    return out


def _shape(kind: int, q):
    """f(q) of kernel ``kind`` on an array of any shape."""
    q = np.asarray(q, float)
    return _shapes(kind, q.ravel()).reshape(q.shape)


@lru_cache(maxsize=None)
def beyond_axis_table(kind: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(ζ, J(ζ), M(ζ))`` on ``TABLE_POINTS`` points of [0, 1] for kernel
    ``kind`` (module docstring), from the projected kernel
    W₁(s) = ∫ σ₂ f(√(s² + t²)) dt by Gauss–Legendre quadrature."""
    s = np.linspace(0.0, 1.0, TABLE_POINTS)
    nodes, weights = np.polynomial.legendre.leggauss(64)
    half = np.sqrt(np.maximum(1.0 - s * s, 0.0))  # the chord's half length at s
    t = 0.5 * half[:, None] * (nodes[None, :] + 1.0)  # t in [0, half]
    W1 = SIGMA[kind, 2] * 2.0 * np.sum(0.5 * half[:, None] * weights * _shape(kind, np.hypot(s[:, None], t)), axis=1)
    # the tails T_k(ζ) = ∫_ζ^1 s^k W₁ ds (trapezoid, fine grid); J = T_1 − ζ T_0, M = T_0
    tail = lambda g: np.concatenate([np.cumsum((0.5 * (g[1:] + g[:-1]) * np.diff(s))[::-1])[::-1], [0.0]])  # noqa: E731
    M = tail(W1)
    return s, tail(s * W1) - s * M, M


class AxisFactors(NamedTuple):
    """What the axis makes of particles at radius r with support H (module docstring)."""

    radius: np.ndarray  #: r̃ = r + 2 H J(r/H), with η = 2π ρ r̃ [m]
    slope: np.ndarray  #: ∂r̃/∂r = 1 − 2 M(r/H)
    grad_h: np.ndarray  #: Φ = 1 + H (J + ζ M) / r̃


def axis_factors(r, H, kind: int) -> AxisFactors:
    """:class:`AxisFactors` of particles at radius ``r`` ≥ 0 with support ``H``
    for kernel ``kind``."""
    zeta_table, J_table, M_table = beyond_axis_table(kind)
    zeta = r / H
    J = np.interp(zeta, zeta_table, J_table, right=0.0)
    M = np.interp(zeta, zeta_table, M_table, right=0.0)
    radius = r + 2.0 * H * J
    return AxisFactors(radius, 1.0 - 2.0 * M, 1.0 + H * (J + zeta * M) / radius)


def axis_density(eta, r, H, kind: int) -> np.ndarray:
    """ρ = η / (2π r̃) of particles at radius ``r`` with support ``H`` whose
    summation density (ring masses, mirror ghosts) is ``η``."""
    return eta / (2.0 * np.pi * axis_factors(r, H, kind).radius)
