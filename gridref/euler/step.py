"""One unsplit MUSCL–Hancock step for the Euler equations (van Leer 1984;
Toro 2009 §14.4; multi-dimensional unsplit form as in Colella 1990 without
transverse Riemann solves).

1. limited primitive slopes ``ΔW_d`` along every direction;
2. predictor ``W^{n+1/2} = W − (Δt/2) Σ_d A_d(W) ΔW_d / Δx_d`` with the
   primitive-variable Jacobians ``A_d``;
3. face states ``W^{n+1/2} ± ΔW_d/2``; a cell whose face states are not
   physical (ρ ≤ 0 or p ≤ 0) falls back to first order (zero slope, no
   predictor) — the positivity fallback;
4. a Riemann flux per face, ``U^{n+1} = U − Δt Σ_d (F_{d,i+1/2} − F_{d,i−1/2})/Δx_d``.

Sums over directions are formed before they are applied, so the update is
exactly symmetric under exchanging x and y on a square grid.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import jax
import jax.numpy as jnp

from gridref.euler.boundaries import N_GHOST, axis_of, with_ghosts
from gridref.euler.reconstruct import LIMITERS, limited_slopes
from gridref.euler.riemann import RIEMANN_SOLVERS
from gridref.euler.state import primitive, rotated, sound_speed


def _crop(a, axes, k=1):
    """``a`` with ``k`` cells removed at both ends of every axis in ``axes``."""
    index = [slice(None)] * a.ndim
    for axis in axes:
        index[axis] = slice(k, a.shape[axis] - k)
    return a[tuple(index)]


def _shifted(a, axis, lo):
    """Cells ``[0, n-1)`` (``lo=True``) or ``[1, n)`` along ``axis``: the two
    sides of every interior face."""
    index = [slice(None)] * a.ndim
    index[axis] = slice(0, -1) if lo else slice(1, None)
    return a[tuple(index)]


def primitive_change(W, dW, d, gamma):
    """``A_d(W) ΔW``: the quasi-linear primitive Euler operator along ``d``,
    ``(u_n Δρ + ρ Δu_n, u_n Δu_k + δ_kd Δp/ρ, u_n Δp + γ p Δu_n)``."""
    rho, un, p = W[0], W[1 + d], W[-1]
    dun, dp = dW[1 + d], dW[-1]
    dvel = [un * dv for dv in dW[1:-1]]
    dvel[d] = dvel[d] + dp / rho
    return (un * dW[0] + rho * dun, *dvel, un * dp + gamma * p * dun)


def stable_dt(U, gamma, dx, cfl, fluid=None):
    """CFL time step ``Δt = C / max_cells Σ_d (|u_d| + c)/Δx_d``; NaN if the
    fluid holds NaN, negative density or negative pressure (the caller
    reports where)."""
    W = primitive(U, gamma)
    c = sound_speed(W, gamma)
    rate = sum((jnp.abs(W[1 + d]) + c) / dx[d] for d in range(len(dx)))
    bad = ~(W[0] > 0.0) | ~(W[-1] > 0.0) | ~jnp.isfinite(rate)
    if fluid is not None:
        rate = jnp.where(fluid, rate, 0.0)
        bad = bad & fluid
    return jnp.where(jnp.any(bad), jnp.nan, cfl / jnp.max(rate))


@dataclass(frozen=True)
class Scheme:
    """Settings of the MUSCL–Hancock scheme (static under ``jax.jit``)."""

    gamma: float
    dx: tuple[float, ...]
    kinds: tuple[str, ...]  # boundary kind per side: x_lo, x_hi[, y_lo, y_hi]
    limiter: str = "mc"
    riemann: str = "hllc"
    cfl: float = 0.8


def muscl_hancock_update(U, dt, states, scheme: Scheme, fill_solids: Callable | None = None):
    """``(U^{n+1}, side_forces)`` after one step of size ``dt``.

    ``U`` is a tuple of conservative arrays; ``states`` holds the primitive
    inflow state of every side (rows in side order; used by ``inflow`` sides
    only). ``side_forces[i]`` is the normal momentum flux integrated over
    side ``i`` (per metre depth in 2D, per square metre in 1D): the
    time-centred force the gas exerts on that side.
    """
    gamma, dx = scheme.gamma, scheme.dx
    dim = len(dx)
    limiter = LIMITERS[scheme.limiter]
    flux = RIEMANN_SOLVERS[scheme.riemann]
    W = primitive(U, gamma)
    if fill_solids is not None:
        W = fill_solids(W)
    Wg = with_ghosts(W, scheme.kinds, states)
    axes = [axis_of(dim, d) for d in range(dim)]
    # every cell of the interior plus one ghost layer
    Wc = tuple(_crop(a, axes, N_GHOST - 1) for a in Wg)
    slopes = [
        tuple(_crop(limited_slopes(a, axes[d], limiter), [b for b in axes if b != axes[d]], N_GHOST - 1) for a in Wg)
        for d in range(dim)
    ]
    changes = [primitive_change(Wc, slopes[d], d, gamma) for d in range(dim)]
    Wh = tuple(w - (0.5 * dt) * sum(ch[k] / dx[d] for d, ch in enumerate(changes)) for k, w in enumerate(Wc))
    faces_ok = True
    for d in range(dim):
        for sign in (-0.5, 0.5):
            faces_ok = faces_ok & (Wh[0] + sign * slopes[d][0] > 0.0) & (Wh[-1] + sign * slopes[d][-1] > 0.0)
    Wh = tuple(jnp.where(faces_ok, a, b) for a, b in zip(Wh, Wc))
    Wh, faces_ok = jax.lax.optimization_barrier((Wh, faces_ok))
    divergence = [0.0] * len(U)
    forces = []
    for d in range(dim):
        s = tuple(jnp.where(faces_ok, a, 0.0) for a in slopes[d])
        others = [b for b in axes if b != axes[d]]
        left = tuple(_crop(_shifted(w + 0.5 * ds, axes[d], True), others) for w, ds in zip(Wh, s))
        right = tuple(_crop(_shifted(w - 0.5 * ds, axes[d], False), others) for w, ds in zip(Wh, s))
        left, right = jax.lax.optimization_barrier((left, right))
        F = rotated(flux(rotated(left, d), rotated(right, d), gamma), d)
        F = jax.lax.optimization_barrier(F)
        inv_dx = 1.0 / dx[d]
        divergence = [acc + (_shifted(f, axes[d], False) - _shifted(f, axes[d], True)) * inv_dx
                      for acc, f in zip(divergence, F)]
        face_area = 1.0 if dim == 1 else dx[1 - d]
        momentum = F[1 + d]
        n = momentum.shape[axes[d]]
        forces += [jnp.sum(jnp.take(momentum, 0, axis=axes[d])) * face_area,
                   jnp.sum(jnp.take(momentum, n - 1, axis=axes[d])) * face_area]
    return tuple(u - dt * div for u, div in zip(U, divergence)), jnp.stack(forces)


def make_stepper(scheme: Scheme, fill_solids=None, fluid=None, reset_solids=None, probe_sampler=None):
    """A jitted ``step(U, t, t_stop, states) -> (U, dt, side_forces, probes)``
    that advances by the CFL step, clipped so it lands on ``t_stop``."""

    def step(U, t, t_stop, states):
        dt = jnp.minimum(stable_dt(U, scheme.gamma, scheme.dx, scheme.cfl, fluid), t_stop - t)
        U_new, forces = muscl_hancock_update(U, dt, states, scheme, fill_solids)
        if reset_solids is not None:
            U_new = reset_solids(U_new)
        probes = probe_sampler(U_new) if probe_sampler is not None else jnp.zeros(0)
        return U_new, dt, forces, probes

    return jax.jit(step)
