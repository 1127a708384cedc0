"""Shock relations: normal shock, shock reflection from a wall, oblique shocks,
the Friedlander blast profile and the Rankine-Hugoniot blast inflow state.

References: J. D. Anderson, *Modern Compressible Flow*, 3rd ed., McGraw-Hill
2003 (ch. 7, moving and reflected normal shocks; ch. 4, oblique shocks and
the theta-beta-M relation); Ames Research Staff, "Equations, tables, and
charts for compressible flow", NACA Report 1135 (1953); E. F. Toro, *Riemann
Solvers and Numerical Methods for Fluid Dynamics*, 3rd ed., Springer 2009,
ch. 3 (Rankine-Hugoniot conditions); G. F. Kinney & K. J. Graham, *Explosive Shocks in Air*, 2nd ed., Springer
1985 (the Friedlander waveform).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from partmesh.compare.exact._inputs import positive, ratio_of_heats
from partmesh.compare.exact.riemann import star_state

#: The inflow blasts of the blast-array scenes (SPEC §4.2): peak overpressure
#: over p0, positive-phase duration t_plus [s] and Friedlander decay alpha.
BLASTS = {
    "moderate": dict(p_peak_ratio=10.924, t_plus=0.473e-3, alpha=4.0),
    "strong": dict(p_peak_ratio=100.924, t_plus=0.5e-3, alpha=2.72),
}

NEGATIVE_PHASES = ("friedlander", "none")


def _mach(name: str, value, *, supersonic: bool = False) -> np.ndarray:
    """A Mach number array, >= 1 (> 1 if ``supersonic``)."""
    value = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(value)) or np.any(value < 1.0) or (supersonic and np.any(value == 1.0)):
        raise ValueError(f"{name} must be finite and {'>' if supersonic else '>='} 1, got {value}.")
    return value


def _jump(mach, gamma):
    """Density ratio, pressure ratio and velocity jump over upstream sound speed
    of a normal shock with upstream Mach number ``mach`` (relative to the shock)."""
    m2 = mach * mach
    density = (gamma + 1.0) * m2 / ((gamma - 1.0) * m2 + 2.0)
    pressure = 1.0 + 2.0 * gamma / (gamma + 1.0) * (m2 - 1.0)
    velocity = 2.0 / (gamma + 1.0) * (mach - 1.0 / mach)
    return density, pressure, velocity


def normal_shock(Ms, rho0, p0, gamma: float = 1.4):
    """State (rho1, u1, p1) behind a normal shock moving at Mach ``Ms`` into gas at rest.

    Lab frame, shock moving in +x at W = Ms a0, a0 = sqrt(gamma p0/rho0)
    (Anderson, Modern Compressible Flow, ch. 7):
    p1/p0 = 1 + 2 gamma/(gamma+1) (Ms^2 - 1),
    rho1/rho0 = (gamma+1) Ms^2 / ((gamma-1) Ms^2 + 2),
    u1 = 2 a0/(gamma+1) (Ms - 1/Ms)  (the induced gas velocity, in +x).
    Vectorised over ``Ms`` (>= 1); ``rho0``, ``p0`` > 0; ``gamma`` > 1.
    """
    gamma = ratio_of_heats(gamma)
    Ms = _mach("Ms", Ms)
    rho0, p0 = positive("rho0", rho0), positive("p0", p0)
    density, pressure, velocity = _jump(Ms, gamma)
    return rho0 * density, np.sqrt(gamma * p0 / rho0) * velocity, p0 * pressure


def reflected_shock(Ms, rho0, p0, gamma: float = 1.4) -> dict:
    """Normal reflection of a shock of Mach ``Ms`` from a rigid end wall.

    The incident shock leaves state 1 = normal_shock(Ms) moving at u1 toward
    the wall; the reflected shock brings the gas to rest (u_r = 0). Its Mach
    number Mr relative to the gas of state 1 solves
    u1 = 2 a1/(gamma+1) (Mr - 1/Mr), i.e. Mr = (k + sqrt(k^2 + 4))/2 with
    k = (gamma+1) u1/(2 a1), which is Anderson's (ch. 7) relation
    Mr/(Mr^2-1) = Ms/(Ms^2-1) sqrt(1 + 2(gamma-1)/(gamma+1)^2 (Ms^2-1)(gamma + 1/Ms^2)),
    in closed form. Then p_r = p1 [1 + 2 gamma/(gamma+1)(Mr^2 - 1)] and
    rho_r = rho1 (gamma+1) Mr^2/((gamma-1) Mr^2 + 2) (Anderson ch. 7).

    Returns a dict with ``p_incident`` (p1), ``p_reflected``, ``rho_reflected``,
    ``reflected_shock_speed`` (lab frame, > 0 = moving away from the wall:
    Mr a1 - u1) and ``Mr``. Vectorised over ``Ms`` (>= 1).
    """
    gamma = ratio_of_heats(gamma)
    rho1, u1, p1 = normal_shock(Ms, rho0, p0, gamma)
    a1 = np.sqrt(gamma * p1 / rho1)
    k = 0.5 * (gamma + 1.0) * u1 / a1
    Mr = 0.5 * (k + np.sqrt(k * k + 4.0))
    density, pressure, _ = _jump(Mr, gamma)
    return {
        "p_incident": p1,
        "p_reflected": p1 * pressure,
        "rho_reflected": rho1 * density,
        "reflected_shock_speed": Mr * a1 - u1,
        "Mr": Mr,
    }


def driver_pressure(Ms, rho0, p0, gamma: float = 1.4) -> float:
    """Pressure of a driver gas at rest, of the same density ``rho0`` (so
    hotter), whose release into gas at rest at (``rho0``, ``p0``) sends a
    shock of Mach ``Ms``: the shock-tube problem (Anderson, Modern
    Compressible Flow, ch. 7) solved as the root p4 of
    p*(p4) = p0 (1 + 2γ/(γ+1)(Ms² − 1)), p* the star pressure of the exact
    Riemann problem (ρ0, 0, p4 | ρ0, 0, p0) (:func:`star_state`)."""
    gamma = ratio_of_heats(gamma)
    Ms = float(_mach("Ms", Ms))
    rho0, p0 = positive("rho0", rho0), positive("p0", p0)
    target = p0 * (1.0 + 2.0 * gamma / (gamma + 1.0) * (Ms * Ms - 1.0))
    if Ms == 1.0:
        return p0
    return brentq(lambda p4: star_state((rho0, 0.0, p4), (rho0, 0.0, p0), gamma)[0] - target, target, 1e9 * p0,
                  xtol=1e-14 * target, rtol=1e-14)


def reflection_coefficient(Ms, gamma: float = 1.4):
    """C_R = (p_r - p0)/(p_i - p0), the reflected over the incident overpressure.

    From the relations of :func:`reflected_shock` (Anderson, Modern Compressible
    Flow, ch. 7). With c = 2 gamma/(gamma+1), p_i/p0 = 1 + c (Ms^2 - 1),
    p_r/p_i = 1 + c (Mr^2 - 1) and Mr^2 - 1 = k Mr = (a0/a1)(Mr/Ms)(Ms^2 - 1),
    C_R = 1 + (a0/a1) (Mr/Ms) (p_i/p0), a form without the 0/0 of the
    definition at Ms = 1. It depends on Ms and gamma only. Limits: C_R -> 2 as
    Ms -> 1 (acoustic doubling) and p_r/p_i -> (3 gamma - 1)/(gamma - 1) as
    Ms -> infinity. Vectorised over ``Ms`` (>= 1).
    """
    gamma = ratio_of_heats(gamma)
    Ms = _mach("Ms", Ms)
    rho1, _, p1 = normal_shock(Ms, 1.0, 1.0, gamma)  # rho0 = p0 = 1, so a0/a1 = sqrt(rho1/p1)
    Mr = reflected_shock(Ms, 1.0, 1.0, gamma)["Mr"]
    return 1.0 + np.sqrt(rho1 / p1) * Mr / Ms * p1


def _deflection(M1, beta, gamma):
    """theta(beta) [rad] of the theta-beta-M relation (Anderson ch. 4)."""
    m2 = M1 * M1
    return np.arctan(2.0 / np.tan(beta) * (m2 * np.sin(beta) ** 2 - 1.0) / (m2 * (gamma + np.cos(2.0 * beta)) + 2.0))


def _beta_at_max_deflection(M1, gamma):
    """Shock angle [rad] of the largest deflection (NACA Report 1135)."""
    m2 = M1 * M1
    sin2 = ((gamma + 1.0) / 4.0 * m2 - 1.0
            + np.sqrt((gamma + 1.0) * ((gamma + 1.0) / 16.0 * m2 * m2 + (gamma - 1.0) / 2.0 * m2 + 1.0))) / (gamma * m2)
    return np.arcsin(np.sqrt(sin2))


def max_deflection(M1, gamma: float = 1.4):
    """Largest flow deflection theta_max [deg] an attached oblique shock can turn at Mach ``M1``.

    theta_max = theta(beta_max) of the theta-beta-M relation (Anderson ch. 4),
    with sin^2 beta_max = [(gamma+1) M1^2/4 - 1 + sqrt((gamma+1)((gamma+1) M1^4/16
    + (gamma-1) M1^2/2 + 1))]/(gamma M1^2) (NACA Report 1135).
    Vectorised over ``M1`` (> 1).
    """
    gamma = ratio_of_heats(gamma)
    M1 = _mach("M1", M1, supersonic=True)
    return np.degrees(_deflection(M1, _beta_at_max_deflection(M1, gamma), gamma))[()]


def theta_beta_mach(M1, theta_deg, gamma: float = 1.4, branch: str = "weak"):
    """Oblique-shock angle beta [deg] for Mach ``M1`` and deflection ``theta_deg``.

    Solves the theta-beta-M relation (Anderson, Modern Compressible Flow, ch. 4)
    tan theta = 2 cot beta (M1^2 sin^2 beta - 1) / (M1^2 (gamma + cos 2 beta) + 2)
    for beta in (asin(1/M1), beta_max] (``branch="weak"``) or [beta_max, 90 deg]
    (``"strong"``), where theta(beta) increases, resp. decreases, monotonically;
    by vectorised bisection to round-off. theta = 0 gives the Mach angle
    asin(1/M1) (weak) or 90 deg (strong). theta above
    :func:`max_deflection` raises ValueError: the shock detaches.
    Vectorised over ``M1`` (> 1) and ``theta_deg`` (>= 0).
    """
    gamma = ratio_of_heats(gamma)
    if branch not in ("weak", "strong"):
        raise ValueError(f"branch must be 'weak' or 'strong', got {branch!r}.")
    M1 = _mach("M1", M1, supersonic=True)
    theta_deg = np.asarray(theta_deg, dtype=float)
    if not np.all(np.isfinite(theta_deg)) or np.any(theta_deg < 0.0):
        raise ValueError(f"theta_deg must be finite and >= 0, got {theta_deg}.")
    theta_b, mach_b, max_b = np.broadcast_arrays(theta_deg, M1, max_deflection(M1, gamma))
    detached = np.flatnonzero(theta_b > max_b)
    if detached.size:
        k = detached[0]
        raise ValueError(f"theta_deg = {theta_b.flat[k]:g} exceeds the maximum deflection theta_max = "
                         f"{max_b.flat[k]:.2f} deg at M1 = {mach_b.flat[k]:g}: the shock detaches.")
    theta = np.radians(theta_deg)
    beta_max = _beta_at_max_deflection(M1, gamma)
    edges = (np.arcsin(1.0 / M1), beta_max) if branch == "weak" else (beta_max, 0.5 * np.pi)
    shape = np.broadcast_shapes(M1.shape, theta.shape)
    low, high = (np.broadcast_to(edge, shape).astype(float) for edge in edges)
    rising = 1.0 if branch == "weak" else -1.0
    for _ in range(64):  # bisection: the bracket shrinks below round-off in 64 halvings
        middle = 0.5 * (low + high)
        below = rising * (_deflection(M1, middle, gamma) - theta) < 0.0
        low, high = np.where(below, middle, low), np.where(below, high, middle)
    return np.degrees(0.5 * (low + high))[()]


def friedlander(t, p_peak, t_plus, alpha, negative_phase: str = "friedlander", xp=np):
    """Friedlander blast overpressure p_o(t) (Kinney & Graham 1985, ch. 7).

    p_o(t) = p_peak (1 - t/t_plus) exp(-alpha t/t_plus) for t >= 0 and 0 for
    t < 0 (before arrival). ``negative_phase="friedlander"`` keeps the formula
    for t > t_plus (the underpressure phase, p_o < 0, decaying to 0);
    ``"none"`` returns 0 for t > t_plus (the gas returns to ambient).
    Vectorised over ``t`` [s]; ``p_peak``, ``t_plus`` > 0, ``alpha`` >= 0.
    ``xp`` is the array namespace ``t`` belongs to (``jax.numpy`` evaluates
    it inside a compiled time loop).
    """
    p_peak, t_plus = positive("p_peak", p_peak), positive("t_plus", t_plus)
    alpha = float(alpha)
    if not np.isfinite(alpha) or alpha < 0.0:
        raise ValueError(f"alpha must be a finite number >= 0, got {alpha}.")
    if negative_phase not in NEGATIVE_PHASES:
        raise ValueError(f"negative_phase must be one of {', '.join(NEGATIVE_PHASES)}, got {negative_phase!r}.")
    t = xp.asarray(t, dtype=float)
    tau = t / t_plus
    p_o = p_peak * (1.0 - tau) * xp.exp(-alpha * xp.maximum(tau, 0.0))
    off = t < 0.0
    if negative_phase == "none":
        off = off | (t > t_plus)
    return xp.where(off, 0.0, p_o)[()]


def rankine_hugoniot_inflow(p_over, rho0, p0, gamma: float = 1.4, xp=np):
    """Gas state (rho, u, p) behind a shock of overpressure ``p_over`` into gas at rest.

    Rankine-Hugoniot relations written with the overpressure p_o = p - p0
    (Toro 2009, ch. 3; Kinney & Graham 1985):
    rho = rho0 [(gamma+1) p_o + 2 gamma p0] / [(gamma-1) p_o + 2 gamma p0],
    u = a0 (p_o/(gamma p0)) sqrt(2 gamma p0 / [(gamma+1) p_o + 2 gamma p0]),
    a0 = sqrt(gamma p0/rho0), p = p0 + p_o. Vectorised over ``p_over``. A
    negative overpressure (Friedlander negative phase) continues the formula
    smoothly (rho < rho0, u < 0; the isentrope and the Hugoniot agree to
    third order in p_o); ``p_over`` must be > -p0 (checked where ``xp`` is
    numpy; a traced ``p_over`` has no value to check).
    """
    gamma = ratio_of_heats(gamma)
    rho0, p0 = positive("rho0", rho0), positive("p0", p0)
    p_over = xp.asarray(p_over, dtype=float)
    if xp is np and (not np.all(np.isfinite(p_over)) or np.any(p_over <= -p0)):
        raise ValueError(f"p_over must be finite and > -p0 = {-p0}, got {p_over}.")
    a0 = np.sqrt(gamma * p0 / rho0)
    rho = rho0 * ((gamma + 1.0) * p_over + 2.0 * gamma * p0) / ((gamma - 1.0) * p_over + 2.0 * gamma * p0)
    u = a0 * p_over / (gamma * p0) * xp.sqrt(2.0 * gamma * p0 / ((gamma + 1.0) * p_over + 2.0 * gamma * p0))
    return rho, u, p0 + p_over
