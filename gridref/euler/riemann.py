"""Approximate Riemann solvers: the numerical flux through a face from the
primitive states on its left (``WL``) and right (``WR``), both given in the
face's normal frame ``(rho, u_n, u_t..., p)`` (see ``state.rotated``).

Every solver has the signature ``flux(WL, WR, gamma) -> F`` (a tuple in the
same frame), so they are interchangeable (``RIEMANN_SOLVERS``). HLLC also
takes detonation products and air (``gas`` a
:class:`~partmesh.gridref.euler.mixture.Mixture`, :mod:`partmesh.gridref.euler.state`),
and then returns one more flux: the volume flux that advects the volume fraction.
"""

from __future__ import annotations

import math

import jax.numpy as jnp
from jax.scipy.special import erf

from partmesh.gridref.euler.state import conservative, normal_flux, parts, scalar_count, sound_speed


def einfeldt_speeds(WL, WR, gamma):
    """Signal speeds ``(S_L, S_R)`` of Einfeldt (1988), HLLE: the extremes of
    the one-sided speeds ``u ∓ c`` and the Roe-averaged ``ũ ∓ c̃`` (Toro 2009
    eq. 10.52), which keep HLL positively conservative."""
    rL, rR, pL, pR = WL[0], WR[0], WL[-1], WR[-1]
    cL2, cR2 = gamma * pL / rL, gamma * pR / rR
    sL, sR = jnp.sqrt(rL), jnp.sqrt(rR)
    wL = sL / (sL + sR)
    wR = 1.0 - wL
    vel = [wL * a + wR * b for a, b in zip(WL[1:-1], WR[1:-1])]
    kin = sum(wL * a * a + wR * b * b for a, b in zip(WL[1:-1], WR[1:-1]))
    # Roe-averaged c̃² = (γ−1)(H̃ − |ũ|²/2) with H = c²/(γ−1) + |u|²/2
    c2 = wL * cL2 + wR * cR2 + 0.5 * (gamma - 1.0) * (kin - sum(c * c for c in vel))
    c = jnp.sqrt(jnp.maximum(c2, 0.0))
    return (jnp.minimum(WL[1] - jnp.sqrt(cL2), vel[0] - c), jnp.maximum(WR[1] + jnp.sqrt(cR2), vel[0] + c))


def davis_speeds(WL, WR, gas):
    """Signal speeds ``S_L = min(u_L − c_L, u_R − c_R)``, ``S_R = max(u_L + c_L, u_R + c_R)``
    (Davis 1988; Toro 2009 eq. 10.48): HLLC's for a mixture, whose Roe average has no closed form."""
    cL, cR = sound_speed(WL, gas), sound_speed(WR, gas)
    return jnp.minimum(WL[1] - cL, WR[1] - cR), jnp.maximum(WL[1] + cL, WR[1] + cR)


def hllc(WL, WR, gas):
    """HLLC flux (Toro, Spruce & Speares 1994; Toro 2009 §10.4):
    ``S* = [p_R − p_L + ρ_L u_L(S_L − u_L) − ρ_R u_R(S_R − u_R)] /
    [ρ_L(S_L − u_L) − ρ_R(S_R − u_R)]``, ``F = F_K + S_K (U*_K − U_K)`` on
    the side ``K`` of the contact that holds the face, with the outer speed
    clipped at zero so the supersonic cases reduce to ``F_L``/``F_R``.

    A mixture's scalars q (per volume) have the star states ``q χ_K``,
    ``χ_K = (S_K − u_K)/(S_K − S*)``, and one more flux is returned, the
    volume flux ``u_K + S_K (χ_K − 1)`` whose divergence the volume fraction's
    non-conservative term takes (Johnsen & Colonius 2006, J. Comput. Phys.
    219, 715, eq. 30): a contact at uniform pressure and velocity stays so."""
    SL, SR = einfeldt_speeds(WL, WR, gas) if not scalar_count(gas) else davis_speeds(WL, WR, gas)
    mL, mR = WL[0] * (SL - WL[1]), WR[0] * (SR - WR[1])
    S_star = (WR[-1] - WL[-1] + WL[1] * mL - WR[1] * mR) / (mL - mR)
    left = S_star >= 0.0
    W = tuple(jnp.where(left, a, b) for a, b in zip(WL, WR))
    SK = jnp.where(left, SL, SR)
    S = jnp.where(left, jnp.minimum(SL, 0.0), jnp.maximum(SR, 0.0))
    rho, vel, scalars, p = parts(W, gas)
    un = vel[0]
    U = conservative(W, gas)
    F = normal_flux(W, gas)
    rho_star = rho * (SK - un) / (SK - S_star)
    E_star = rho_star * (U[-1] / rho + (S_star - un) * (S_star + p / (rho * (SK - un))))
    U_star = (rho_star, rho_star * S_star, *(rho_star * c for c in vel[1:]),
              *(q * (SK - un) / (SK - S_star) for q in scalars), E_star)
    flux = tuple(f + S * (us - u) for f, us, u in zip(F, U_star, U))
    if not scalar_count(gas):
        return flux
    return (*flux, un + S * ((SK - un) / (SK - S_star) - 1.0))


def hll(WL, WR, gamma):
    """HLL flux (Harten, Lax & van Leer 1983) with Einfeldt speeds:
    ``F = (S_R⁺ F_L − S_L⁻ F_R + S_L⁻ S_R⁺ (U_R − U_L)) / (S_R⁺ − S_L⁻)``."""
    SL, SR = einfeldt_speeds(WL, WR, gamma)
    SL, SR = jnp.minimum(SL, 0.0), jnp.maximum(SR, 0.0)
    inv = 1.0 / (SR - SL)
    return tuple(
        (SR * fl - SL * fr + SL * SR * (ur - ul)) * inv
        for fl, fr, ul, ur in zip(normal_flux(WL, gamma), normal_flux(WR, gamma),
                                  conservative(WL, gamma), conservative(WR, gamma))
    )


def rusanov(WL, WR, gamma):
    """Rusanov (local Lax–Friedrichs) flux:
    ``F = ½(F_L + F_R) − ½ S_max (U_R − U_L)``, ``S_max = max(|u_L|+c_L, |u_R|+c_R)``."""
    smax = jnp.maximum(jnp.abs(WL[1]) + jnp.sqrt(gamma * WL[-1] / WL[0]),
                       jnp.abs(WR[1]) + jnp.sqrt(gamma * WR[-1] / WR[0]))
    return tuple(
        0.5 * (fl + fr) - 0.5 * smax * (ur - ul)
        for fl, fr, ul, ur in zip(normal_flux(WL, gamma), normal_flux(WR, gamma),
                                  conservative(WL, gamma), conservative(WR, gamma))
    )


def half_range_flux(W, gamma, sign):
    """The flux carried through a face by the molecules of the equilibrium
    gas ``W`` (normal frame) that cross it in the direction ``sign`` (+1:
    u_n > 0, −1: u_n < 0): the half-range moments of its Maxwellian (Pullin
    1980, J. Comput. Phys. 34, 231). With θ = p/ρ, s = u_n/√(2θ),
    W± = ½(1 ± erf s), D = √(θ/(2π)) e^{−s²}:

        F_ρ = ρ(u_n W± ± D),   F_n = (ρu_n² + p) W± ± ρ u_n D,
        F_t = u_t F_ρ,         F_E = u_n (E + p) W± ± (E + p/2) D,

    E the total energy per volume (internal degrees of freedom included, as
    the molecules carry them)."""
    rho, un, vt, p = W[0], W[1], W[2:-1], W[-1]
    theta = p / rho
    s = un / jnp.sqrt(2.0 * theta)
    share = 0.5 * (1.0 + sign * erf(s))
    D = sign * jnp.sqrt(theta / (2.0 * math.pi)) * jnp.exp(-s * s)
    E = conservative(W, gamma)[-1]
    mass = rho * (un * share + D)
    return (mass, (rho * un * un + p) * share + rho * un * D, *(c * mass for c in vt),
            un * (E + p) * share + (E + 0.5 * p) * D)


def efm(WL, WR, gamma):
    """Pullin's Equilibrium Flux Method: the molecules of the left gas moving
    right plus those of the right gas moving left,
    ``F = F⁺(W_L) + F⁻(W_R)`` (:func:`half_range_flux`) — the flux of the
    equilibrium DSMC in its infinite-particle limit (SPEC §3.3)."""
    return tuple(a + b for a, b in zip(half_range_flux(WL, gamma, 1.0), half_range_flux(WR, gamma, -1.0)))


RIEMANN_SOLVERS = {"hllc": hllc, "hll": hll, "rusanov": rusanov, "efm": efm}
