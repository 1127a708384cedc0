r"""A planar Chapman–Jouguet detonation from a rigid wall and the Taylor wave behind it.

A detonation initiated at the wall x = 0 at t = 0 runs into the explosive at the CJ speed D
(:meth:`partmesh.compare.materials.JWL.cj_state`). Behind the front the products expand on the principal
isentrope (the one through the CJ state) in a centred simple wave, the Taylor wave (Taylor 1950, Proc. R.
Soc. A 200, 235; Fickett & Davis 1979, *Detonation*, §2C): along the forward characteristics
x/t = u + c, and the backward Riemann invariant carries the CJ state's,

.. math::  u - \int_{\rho_{CJ}}^{\rho} \frac{c_s(r)}{r}\,dr = u_{CJ},

so u falls from u_CJ at the front (x/t = D, where u + c = D: the CJ point is sonic) to 0 at
x/t = c_rest, behind which the products rest against the wall in a uniform state. The solution depends on
ξ = x/t only. For an ideal gas of γ (JWL with A = B → 0, ω = γ − 1) it is the closed form
u = 2(ξ − D/2)/(γ + 1), c = D/2 + (γ − 1)u/2, with the rest state at ξ = D/2.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from partmesh.compare.exact._inputs import axis, output_times
from partmesh.compare.schema import result

#: the wave is followed down to this fraction of the CJ density (the rest state lies well above it)
LOWEST_DENSITY = 0.2


@dataclass(frozen=True)
class TaylorWave:
    """The products behind a planar CJ detonation from a rigid wall: ``D`` the front's speed, ``rest`` the ξ
    = x/t below which the products rest, ``rho_rest`` and ``p_rest`` their state there; :meth:`at` samples
    the whole profile."""

    material: object
    D: float
    rest: float
    rho_rest: float
    p_rest: float
    _C: float
    _invariant: object
    _cj_rho: float

    def _state(self, rho):
        """(u, c, p, e) on the principal isentrope at density ``rho`` within the wave."""
        e = float(self.material.isentrope_energy(rho, self._C))
        c = float(self.material.sound_speed(rho, e))
        return float(self._invariant(rho)[0]), c, float(self.material.pressure(rho, e)), e

    def at(self, xi):
        """``(rho, u, p, e)`` at ξ = x/t (arrays like ``xi``): the rest state for ξ ≤ :attr:`rest`, the wave up
        to the front, the unreacted explosive (ρ₀, at rest, p = 0, e = 0) beyond ξ = D."""
        xi = np.asarray(xi, dtype=float)
        out = np.empty((4,) + xi.shape)
        for index, x in np.ndenumerate(xi):
            if x > self.D:
                out[(slice(None),) + index] = (self.material.rho0, 0.0, 0.0, 0.0)
                continue
            if x <= self.rest:
                rho = self.rho_rest
            else:
                rho = brentq(lambda r: sum(self._state(r)[:2]) - x, self.rho_rest, self._cj_rho, xtol=1e-13,
                             rtol=1e-15)
            u, _, p, e = self._state(rho)
            out[(slice(None),) + index] = (rho, max(u, 0.0) if x > self.rest else 0.0, p, e)
        return out[0], out[1], out[2], out[3]


def taylor_wave(material) -> TaylorWave:
    """The planar CJ detonation of ``material`` (a :class:`partmesh.compare.materials.JWL`) from a rigid wall
    and its Taylor wave."""
    cj = material.cj_state()
    C = material.isentrope(cj.rho, cj.p)

    def speed_over_density(rho, _):
        return [float(material.sound_speed(rho, material.isentrope_energy(rho, C))) / rho]

    lowest = LOWEST_DENSITY * cj.rho
    path = solve_ivp(speed_over_density, (cj.rho, lowest), [cj.u], dense_output=True, rtol=1e-12, atol=1e-9)
    invariant = path.sol
    rho_rest = brentq(lambda r: invariant(r)[0], lowest, cj.rho, xtol=1e-13, rtol=1e-15)
    e_rest = float(material.isentrope_energy(rho_rest, C))
    return TaylorWave(material=material, D=cj.D, rest=float(material.sound_speed(rho_rest, e_rest)),
                      rho_rest=rho_rest, p_rest=float(material.pressure(rho_rest, e_rest)), _C=C,
                      _invariant=invariant, _cj_rho=cj.rho)


def planar_detonation(material, x, times, length: float, p_ahead: float = 0.0,
                      case: str = "detonation_1d") -> xr.Dataset:
    """The detonation of a slab ``0 ≤ x ≤ length`` of ``material`` from the rigid wall x = 0, as a result
    Dataset on the points ``x`` at ``times``, up to the time the front reaches the slab's far side: the
    Taylor wave (:func:`taylor_wave`) behind the front, the unreacted explosive at rest (density ρ₀, pressure
    ``p_ahead``, energy e₀) ahead of it; NaN beyond the slab, where the air's state is not part of this
    solution. Fields rho, u, p, e."""
    wave = taylor_wave(material)
    x = axis("x", x)
    times = output_times(times)
    if times[-1] * wave.D > length:
        raise ValueError(f"the front reaches the slab's far side at t = {length / wave.D:.4g} s; the latest time "
                         f"asked for is {times[-1]:.4g} s.")
    rows = []
    for t in times:
        ahead = x > wave.D * t
        xi = np.where(ahead | (t == 0.0), 0.0, x / max(t, 1e-300))
        rho, u, p, e = wave.at(xi)
        state = [np.where(ahead, a, b) for a, b in zip((material.rho0, 0.0, p_ahead, material.e0), (rho, u, p, e))]
        rows.append([np.where(x > length, np.nan, f) for f in state])
    rho, u, p, e = (np.stack(field) for field in zip(*rows))
    return result(case=case, method="exact", scheme="CJ detonation from a rigid wall and its Taylor wave",
                  x=x, times=times, dx=float(np.mean(np.diff(x))), fields={"rho": rho, "u": u, "p": p, "e": e},
                  parameters={"material": material.name, "length": float(length), "D": wave.D})
