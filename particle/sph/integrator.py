"""One step of gas SPH: the predictor–corrector leapfrog (kick–drift–kick
with a predicted velocity for the velocity-dependent terms; Price 2012,
J. Comput. Phys. 231, 759, §2.9):

    v^{n+½} = v^n + ½Δt a^n,   x^{n+1} = x^n + Δt v^{n+½},
    a^{n+1} = a(x^{n+1}, v^n + Δt a^n),   v^{n+1} = v^{n+½} + ½Δt a^{n+1},

likewise for the specific internal energy, then the viscosity and
conduction switches (Cullen & Dehnen 2010) at the new state. Shared by the
``sph`` method and the particle part of ``hybrid``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable

import numpy as np

from partmesh.particle.sph.particles import reflect_at_plane_walls
from partmesh.particle.sph.switches import conduction_switch, cullen_dehnen
from partmesh.particle.sph.wall_reflection import reflect_into_fluid

#: neighbour lists are built for this multiple of the predicted support; the
#: margin lets the support grow in the density solve and, as a Verlet skin,
#: the particles move for a few steps before the next search
SEARCH_SLACK = 1.25
#: steps of support growth (at the rate ∇·v/d) a new search's lists allow for
LOOKAHEAD_STEPS = 4
#: a run whose time step falls below this fraction of its duration (more than 1e9 steps to go) has run away
MIN_STEP_FRACTION = 1e-9


class Unstable(FloatingPointError):
    """A step that left a particle with a non-positive internal energy or a non-finite velocity, or a
    time step that collapsed."""


def time_step(P, E, cfl: float, shortest: float = 0.0) -> float:
    """The step Δt = cfl min_i ½ H_i/(v_sig,i + |v_i|) (the signal speed of
    the viscosity, Monaghan 1997, J. Comput. Phys. 136, 298, plus the
    particle's own speed) of the particles ``P`` with their evaluation
    ``E``. Raises :class:`Unstable`, naming the particle that sets it,
    where it falls below ``shortest``: a particle running away with speed
    and energy (positive and finite, so no step catches it) would otherwise
    stall the run at an ever shorter step."""
    speed = E.vsig + np.linalg.norm(P.v, axis=1)
    limits = 0.5 * E.H / speed
    k = int(np.argmin(limits))
    dt = cfl * float(limits[k])
    if not dt >= shortest:
        raise Unstable(f"the time step fell to {dt:.3g} s: the particle at x = {P.x[k].round(6).tolist()} m moves at "
                       f"{np.linalg.norm(P.v[k]):.3g} m/s with signal speed {E.vsig[k]:.3g} m/s and specific internal "
                       f"energy {P.u[k]:.3g} J/kg")
    return dt


@dataclass(frozen=True)
class Switches:
    """Bounds of the Cullen–Dehnen viscosity α and the ceiling of the conduction switch."""

    alpha_max: float
    alpha_min: float
    alpha_u: float


def leapfrog(sph, P, E, dt: float, switches: Switches, imposed=None,
             joining=None, retained: Callable | None = None):
    """The fluid particles ``P`` (with ``E``, their evaluation) advanced by
    ``dt``, with their new evaluation and the number of particles the
    walls had to reflect: ``(P_new, E_new, reflected)``. ``P`` is left as
    it was (a failed step keeps the last consistent state).

    ``imposed`` are the particles whose state is set from outside at the
    new time, ``(x, v, rho, u, H, m)`` (neighbours only: an inflow buffer,
    the boundary particles of ``hybrid``); ``joining`` are the particles
    that join the fluid over the step (appended after the drift); ``retained(Q)`` is True for the particles of ``Q`` that stay (None: all).
    Raises :class:`Unstable` (a particle's energy turned non-positive) or
    ``FloatingPointError`` (the density solve failed), saying where."""
    dim = P.x.shape[1]
    Q = dataclasses.replace(P)
    v_half, u_half = P.v + 0.5 * dt * E.dvdt, P.u + 0.5 * dt * E.dudt
    # predicted support: dH/dt = H ∇·v / d, the guess for the next density solve
    Q.H = E.H * np.exp(dt * E.div_v / dim)
    v_pred, u_pred = Q.v + dt * E.dvdt, Q.u + dt * E.dudt
    Q.x = sph.verlet.wrapped(Q.x + dt * v_half)
    # the safeguard: a particle the walls did not stop is mirrored back into the fluid
    Q.x, v_half, v_pred, reflected = reflect_at_plane_walls(sph.scene, Q.x, v_half, v_pred)
    if sph.wall is not None:
        Q.x, v_half, v_pred, more = reflect_into_fluid(sph.scene.obstacles, Q.x, v_half, v_pred)
        reflected += more
    div_old = E.div_v
    if joining is not None:
        Q.append(joining)
        v_half, v_pred = np.concatenate([v_half, joining.v]), np.concatenate([v_pred, joining.v])
        u_half, u_pred = np.concatenate([u_half, joining.u]), np.concatenate([u_pred, joining.u])
        div_old = np.concatenate([div_old, np.zeros(joining.x.shape[0])])
    stay = None if retained is None else retained(Q)
    if stay is not None and not stay.all():
        Q.keep(stay)
        v_half, v_pred, u_half, u_pred, div_old = (a[stay] for a in (v_half, v_pred, u_half, u_pred, div_old))
    growth = np.exp(np.clip(div_old, 0.0, None) * (LOOKAHEAD_STEPS * dt / dim))
    E_new = sph.evaluate(Q, Q.x, v_pred, u_pred, imposed, np.minimum(growth, SEARCH_SLACK))
    v_new, u_new = v_half + 0.5 * dt * E_new.dvdt, u_half + 0.5 * dt * E_new.dudt
    if not (np.all(np.isfinite(v_new)) and np.all(u_new > 0)):
        k = int(np.flatnonzero(~(u_new > 0) | ~np.isfinite(v_new).all(axis=1))[0])
        raise Unstable(f"internal energy {u_new[k]:.3g} at x = {Q.x[k].round(6).tolist()} m")
    Q.alpha_u = conduction_switch(Q.alpha_u, E_new.lap_u, u_new, E_new.vsig, E_new.H, dt, switches.alpha_u, 0.0)
    Q.alpha = cullen_dehnen(Q.alpha, E_new.div_v, div_old, E_new.curl_v, E_new.vsig, E_new.H, dt,
                            switches.alpha_max, switches.alpha_min)
    Q.v, Q.u, Q.H, Q.rho = v_new, u_new, E_new.H, E_new.rho
    return Q, E_new, reflected
