"""Exact Riemann solver for the 1D Euler equations of an ideal gas, vacuum included.

Reference: E. F. Toro, *Riemann Solvers and Numerical Methods for Fluid
Dynamics*, 3rd ed., Springer 2009, chapter 4: the pressure function (§4.2),
the Newton iteration and its initial guesses (§4.3), the sampling of the
self-similar solution (§4.5) and the vacuum cases (§4.6: vacuum initially on
the right, on the left, and generated in the middle when the
pressure-positivity condition u_R - u_L < 2 (a_L + a_R)/(gamma - 1) fails).

States are ``(rho, u, p)`` tuples. A vacuum state is ``rho = p = 0`` (its
velocity is ignored). In a vacuum region of the solution the velocity is
undefined; :func:`sample` returns ``u = xi`` there, the free-streaming value,
which is continuous with the neighbouring rarefaction fans (their velocity
equals the front speed at the vacuum front) and Galilean invariant; ``rho``,
``p`` and ``e`` are 0.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from partmesh.compare.exact._inputs import axis, internal_energy, output_times, ratio_of_heats
from partmesh.compare.schema import result

#: relative change of p* at which the Newton iteration stops
RTOL = 1e-14
MAX_ITERATIONS = 100


def _state(name: str, state) -> tuple[float, float, float]:
    try:
        rho, u, p = (float(v) for v in state)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a (rho, u, p) tuple of three numbers, got {state!r}.") from None
    vacuum = rho == 0.0 and p == 0.0
    if not np.isfinite(u) or not (vacuum or (np.isfinite(rho) and np.isfinite(p) and rho > 0.0 and p > 0.0)):
        raise ValueError(f"{name} must have rho > 0 and p > 0 (or rho = p = 0 for vacuum) and finite u, "
                         f"got {(rho, u, p)}.")
    return rho, u, p


def _pressure_function(p, rho_k, p_k, gamma):
    """f_K(p) and f_K'(p) for one side (Toro §4.2)."""
    a_k = np.sqrt(gamma * p_k / rho_k)
    if p > p_k:  # shock
        a_coef = 2.0 / ((gamma + 1.0) * rho_k)
        b_coef = (gamma - 1.0) / (gamma + 1.0) * p_k
        root = np.sqrt(a_coef / (b_coef + p))
        return (p - p_k) * root, root * (1.0 - 0.5 * (p - p_k) / (b_coef + p))
    # rarefaction; (p/p_K)^z - 1 written with expm1 and, near p_K, log1p to stay accurate
    log_ratio = np.log1p((p - p_k) / p_k) if p > 0.5 * p_k else np.log(p / p_k)
    f = 2.0 * a_k / (gamma - 1.0) * np.expm1((gamma - 1.0) / (2.0 * gamma) * log_ratio)
    return f, (p / p_k) ** (-(gamma + 1.0) / (2.0 * gamma)) / (rho_k * a_k)


def _initial_guess(left, right, gamma):
    """Toro §4.3 (subroutine GUESSP): PVRS where the pressure ratio is small
    and the PVRS value lies between the data, else the two-rarefaction (TRRS)
    or two-shock (TSRS) approximation."""
    (rho_l, u_l, p_l), (rho_r, u_r, p_r) = left, right
    a_l, a_r = np.sqrt(gamma * p_l / rho_l), np.sqrt(gamma * p_r / rho_r)
    p_pv = max(0.0, 0.5 * (p_l + p_r) - 0.125 * (u_r - u_l) * (rho_l + rho_r) * (a_l + a_r))
    p_min, p_max = min(p_l, p_r), max(p_l, p_r)
    if p_max / p_min <= 2.0 and p_min <= p_pv <= p_max:
        return p_pv
    if p_pv < p_min:
        z = (gamma - 1.0) / (2.0 * gamma)
        return ((a_l + a_r - 0.5 * (gamma - 1.0) * (u_r - u_l)) / (a_l / p_l**z + a_r / p_r**z)) ** (1.0 / z)
    g_l = np.sqrt(2.0 / ((gamma + 1.0) * rho_l) / (p_pv + (gamma - 1.0) / (gamma + 1.0) * p_l))
    g_r = np.sqrt(2.0 / ((gamma + 1.0) * rho_r) / (p_pv + (gamma - 1.0) / (gamma + 1.0) * p_r))
    return max((g_l * p_l + g_r * p_r - (u_r - u_l)) / (g_l + g_r), 1e-8 * p_min)


def _newton(left, right, gamma):
    """p* and u* of a problem without vacuum (Toro §4.2-4.3), by Newton iteration."""
    (rho_l, u_l, p_l), (rho_r, u_r, p_r) = left, right
    p = _initial_guess(left, right, gamma)
    sound_scale = 2.0 * (np.sqrt(gamma * p_l / rho_l) + np.sqrt(gamma * p_r / rho_r)) / (gamma - 1.0)
    for _ in range(MAX_ITERATIONS):
        f_l, df_l = _pressure_function(p, rho_l, p_l, gamma)
        f_r, df_r = _pressure_function(p, rho_r, p_r, gamma)
        residual = f_l + f_r + u_r - u_l
        step = residual / (df_l + df_r)
        # f sums terms of size |f_K|, 2 a_K/(gamma-1), |u_L| and |u_R| that may nearly cancel:
        # a residual at their round-off level is as converged as p* can be in double precision
        at_round_off = abs(residual) <= 8.0 * np.finfo(float).eps * (
            abs(f_l) + abs(f_r) + abs(u_l) + abs(u_r) + sound_scale)
        if at_round_off or abs(step) <= RTOL * p:
            return p, 0.5 * (u_l + u_r) + 0.5 * (f_r - f_l)
        # f is increasing and concave: a step below zero restarts from below the root
        p = p - step if p - step > 0.0 else 1e-6 * p
    raise RuntimeError(f"the Newton iteration for p* did not converge in {MAX_ITERATIONS} iterations.")


def _solve(left, right, gamma):
    """(p*, u*, s_left, s_right): the solution is the left wave for xi <= s_left,
    the right wave for xi > s_right and vacuum in between (empty unless vacuum)."""
    (rho_l, u_l, p_l), (rho_r, u_r, p_r) = left, right
    if rho_l == 0.0 and rho_r == 0.0:
        raise ValueError("left and right cannot both be vacuum (rho = p = 0): there is no gas to solve for.")
    if rho_r == 0.0:  # Toro §4.6, right vacuum: left rarefaction into vacuum, front at u_L + 2 a_L/(gamma - 1)
        front = u_l + 2.0 * np.sqrt(gamma * p_l / rho_l) / (gamma - 1.0)
        return 0.0, front, front, np.inf
    if rho_l == 0.0:  # Toro §4.6, left vacuum
        front = u_r - 2.0 * np.sqrt(gamma * p_r / rho_r) / (gamma - 1.0)
        return 0.0, front, -np.inf, front
    a_l, a_r = np.sqrt(gamma * p_l / rho_l), np.sqrt(gamma * p_r / rho_r)
    if 2.0 * (a_l + a_r) / (gamma - 1.0) <= u_r - u_l:  # Toro §4.6, pressure positivity violated
        front_l, front_r = u_l + 2.0 * a_l / (gamma - 1.0), u_r - 2.0 * a_r / (gamma - 1.0)
        return 0.0, (front_l if front_l == front_r else np.nan), front_l, front_r
    p_star, u_star = _newton(left, right, gamma)
    return p_star, u_star, u_star, u_star


def star_state(left, right, gamma: float = 1.4) -> tuple[float, float]:
    """Pressure p* and velocity u* of the star region (Toro 2009, ch. 4).

    p* is the root of f(p) = f_L(p, W_L) + f_R(p, W_R) + u_R - u_L = 0
    (Toro §4.2), with f_K(p) = (p - p_K) sqrt(A_K/(p + B_K)) for a shock
    (p > p_K; A_K = 2/((gamma+1) rho_K), B_K = (gamma-1)/(gamma+1) p_K) and
    f_K(p) = 2 a_K/(gamma-1) [(p/p_K)^((gamma-1)/(2 gamma)) - 1] for a
    rarefaction; u* = (u_L + u_R)/2 + (f_R(p*) - f_L(p*))/2. Newton iteration
    from Toro's adaptive PVRS/TRRS/TSRS guess (§4.3), stopped when the Newton
    step is below 1e-14 p* or, where the terms of f nearly cancel and 1e-14 is
    beyond double precision, when f(p*) is at the round-off level of its terms.

    Vacuum (Toro §4.6): p* = 0. With vacuum on one side u* is the speed of
    the gas-vacuum front (u_L + 2 a_L/(gamma-1) or u_R - 2 a_R/(gamma-1)).
    When vacuum is generated in the middle (u_R - u_L >= 2 (a_L + a_R)/(gamma-1))
    there is no single contact speed and u* is NaN.

    ``left`` and ``right`` are (rho, u, p) tuples; ``gamma`` > 1.
    """
    gamma = ratio_of_heats(gamma)
    p_star, u_star, _, _ = _solve(_state("left", left), _state("right", right), gamma)
    return float(p_star), float(u_star)


def _shock(state, p_star, gamma):
    """Speed and density behind a left shock to p* > p (Toro §4.5)."""
    rho, u, p = state
    a = np.sqrt(gamma * p / rho)
    g1 = (gamma - 1.0) / (gamma + 1.0)
    speed = u - a * np.sqrt((gamma + 1.0) / (2.0 * gamma) * p_star / p + (gamma - 1.0) / (2.0 * gamma))
    return speed, rho * (p_star / p + g1) / (g1 * p_star / p + 1.0)


def _fan_edges(state, p_star, u_star, gamma):
    """Head and tail speeds of a left rarefaction to p* ≤ p and the density behind it (Toro §4.5)."""
    rho, u, p = state
    a = np.sqrt(gamma * p / rho)
    return u - a, u_star - a * (p_star / p) ** ((gamma - 1.0) / (2.0 * gamma)), rho * (p_star / p) ** (1.0 / gamma)


def _fan(state, gamma, xi):
    """(rho, u, p) inside a left rarefaction fan at xi (Toro §4.5)."""
    rho, u, p = state
    a = np.sqrt(gamma * p / rho)
    base = np.clip(2.0 / (gamma + 1.0) + (gamma - 1.0) / (gamma + 1.0) / a * (u - xi), 0.0, 1.0)  # in [0, 1]
    return (rho * base ** (2.0 / (gamma - 1.0)),
            2.0 / (gamma + 1.0) * (a + 0.5 * (gamma - 1.0) * u + xi),
            p * base ** (2.0 * gamma / (gamma - 1.0)))


def _left_wave(state, p_star, u_star, gamma, xi):
    """Solution left of the contact (xi <= u*), Toro §4.5: a shock or a rarefaction fan, at the array ``xi``."""
    if p_star > state[2]:
        speed, rho_star = _shock(state, p_star, gamma)
        behind = xi >= speed
        return tuple(np.where(behind, k_star, k) for k, k_star in zip(state, (rho_star, u_star, p_star)))
    head, tail, rho_star = _fan_edges(state, p_star, u_star, gamma)
    ahead, behind = xi < head, xi > tail
    return tuple(np.select([ahead, behind], [k, k_star], f)
                 for k, k_star, f in zip(state, (rho_star, u_star, p_star), _fan(state, gamma, xi)))


def _left_wave_at(state, p_star, u_star, gamma, xi: float):
    """:func:`_left_wave` at one point: the same formulas, chosen by branching (no array selection: an
    inflow face samples one point per step)."""
    if p_star > state[2]:
        speed, rho_star = _shock(state, p_star, gamma)
        return (rho_star, u_star, p_star) if xi >= speed else state
    head, tail, rho_star = _fan_edges(state, p_star, u_star, gamma)
    if xi < head:
        return state
    if xi > tail:
        return rho_star, u_star, p_star
    return _fan(state, gamma, xi)


def sample(left, right, gamma: float, xi) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The self-similar solution W(xi) = (rho, u, p) at xi = (x - x0)/t (Toro §4.5).

    Left of the contact (xi <= u*): W_L ahead of the left wave, the star
    state behind it; a left shock moves at S_L = u_L - a_L sqrt((gamma+1)/(2 gamma)
    p*/p_L + (gamma-1)/(2 gamma)) with rho*_L = rho_L (p*/p_L + g)/(g p*/p_L + 1),
    g = (gamma-1)/(gamma+1); a left rarefaction spans
    u_L - a_L < xi < u* - a*_L with rho*_L = rho_L (p*/p_L)^(1/gamma) and the fan
    rho = rho_L [2/(gamma+1) + g/a_L (u_L - xi)]^(2/(gamma-1)),
    u = 2/(gamma+1) [a_L + (gamma-1)/2 u_L + xi],
    p = p_L [2/(gamma+1) + g/a_L (u_L - xi)]^(2 gamma/(gamma-1)).
    The right side is the mirror image (x -> -x). Vacuum regions (Toro §4.6)
    have rho = p = 0 and u = xi. Vectorised over ``xi`` (any shape).
    """
    gamma = ratio_of_heats(gamma)
    left, right = _state("left", left), _state("right", right)
    xi = np.asarray(xi, dtype=float)
    p_star, _, s_left, s_right = _solve(left, right, gamma)
    if xi.ndim == 0:
        return _sample_at(left, right, gamma, float(xi), p_star, s_left, s_right)
    rho, u, p = np.zeros_like(xi), xi.copy(), np.zeros_like(xi)
    on_left, on_right = xi <= s_left, xi > s_right
    if left[0] > 0.0:
        for out, value in zip((rho, u, p), _left_wave(left, p_star, s_left, gamma, xi)):
            out[on_left] = np.broadcast_to(value, xi.shape)[on_left]
    if right[0] > 0.0:
        mirror = (right[0], -right[1], right[2])
        r_rho, r_u, r_p = _left_wave(mirror, p_star, -s_right, gamma, -xi)
        for out, value in zip((rho, u, p), (r_rho, -np.asarray(r_u), r_p)):
            out[on_right] = np.broadcast_to(value, xi.shape)[on_right]
    return rho, u, p


def _sample_at(left, right, gamma, xi: float, p_star, s_left, s_right):
    """:func:`sample` at one point, as 0-d arrays."""
    if xi <= s_left and left[0] > 0.0:
        w = _left_wave_at(left, p_star, s_left, gamma, xi)
    elif xi > s_right and right[0] > 0.0:
        rho, u, p = _left_wave_at((right[0], -right[1], right[2]), p_star, -s_right, gamma, -xi)
        w = rho, -u, p
    else:
        w = 0.0, xi, 0.0
    return tuple(np.asarray(k, dtype=float) for k in w)


def riemann(left, right, x, times, x0: float = 0.5, gamma: float = 1.4, case: str = "sod") -> xr.Dataset:
    """The exact solution of a 1D Riemann problem as a partmesh result Dataset.

    Initial data W(x, 0) = W_L for x < x0 and W_R for x >= x0; for t > 0
    W(x, t) = sample(left, right, gamma, (x - x0)/t) (Toro 2009, ch. 4).
    Fields rho, u, p and e = p/((gamma-1) rho) (0 in vacuum) on dims
    (time, x); ``dx`` is the mean spacing of ``x``; ``method = "exact"``.
    """
    gamma = ratio_of_heats(gamma)
    left, right = _state("left", left), _state("right", right)
    x = axis("x", x)
    times = output_times(times)
    x0 = float(x0)
    if not np.isfinite(x0):
        raise ValueError(f"x0 must be a finite number, got {x0}.")
    rows = []
    for t in times:
        if t == 0.0:
            rows.append(tuple(np.where(x < x0, left[k], right[k]) for k in range(3)))
        else:
            rows.append(sample(left, right, gamma, (x - x0) / t))
    rho, u, p = (np.stack(field) for field in zip(*rows))
    return result(
        case=case, method="exact", scheme="exact Riemann solver (Toro 2009 ch. 4, vacuum included)",
        x=x, times=times, dx=float(np.mean(np.diff(x))),
        fields={"rho": rho, "u": u, "p": p, "e": internal_energy(p, rho, gamma)},
        parameters={"left": list(left), "right": list(right), "x0": x0, "gamma": gamma},
    )
