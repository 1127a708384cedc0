"""Noh's implosion problem: cold gas streaming uniformly toward a point, line or plane.

Reference: W. F. Noh, "Errors for calculations of strong shocks using an
artificial viscosity and an artificial heat flux", J. Comput. Phys. 72,
78-120 (1987). Gas of density rho0 moves toward the centre at speed
u0 with zero pressure; a shock reflects from the centre and moves out at
D = (gamma - 1) u0/2. Behind it the gas is at rest with
rho = rho0 ((gamma+1)/(gamma-1))^j and e = u0^2/2, so
p = (gamma - 1) rho e; ahead of it the converging flow has compressed the gas
to rho = rho0 (1 + u0 t/r)^(j-1), with velocity -u0 toward the centre.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from partmesh.compare.exact._inputs import (
    axis,
    geometry_index,
    internal_energy,
    non_negative,
    output_times,
    positive,
    ratio_of_heats,
)
from partmesh.compare.schema import result


def noh_profile(r, t, gamma: float = 5.0 / 3.0, rho0: float = 1.0, u0: float = 1.0,
                geometry: str = "cylindrical", p0: float = 0.0):
    """Density, radial velocity and pressure (rho, u, p) of Noh's problem at radius ``r``, time ``t``.

    Noh (1987): shock radius R = D t with D = (gamma-1) u0/2; for r < R
    rho = rho0 ((gamma+1)/(gamma-1))^j, u = 0, p = (gamma-1) rho u0^2/2;
    for r >= R rho = rho0 (1 + u0 t/r)^(j-1), u = -u0, p = ``p0`` (0 in the
    exact solution; a small positive value keeps e and the sound speed finite).
    j = 1, 2, 3 for ``geometry`` planar, cylindrical, spherical.
    Vectorised over ``r`` (>= 0); ``t`` >= 0.
    """
    j = geometry_index(geometry)
    gamma = ratio_of_heats(gamma)
    rho0, u0 = positive("rho0", rho0), positive("u0", u0)
    t, p0 = non_negative("t", t), non_negative("p0", p0)
    r = np.asarray(r, dtype=float)
    if not np.all(np.isfinite(r)) or np.any(r < 0.0):
        raise ValueError("r must be finite and >= 0.")
    rho_post = rho0 * ((gamma + 1.0) / (gamma - 1.0)) ** j
    shocked = r < 0.5 * (gamma - 1.0) * u0 * t
    with np.errstate(divide="ignore", invalid="ignore"):
        rho_pre = rho0 * (1.0 + np.where(r > 0.0, u0 * t / r, 0.0)) ** (j - 1)
    rho = np.where(shocked, rho_post, rho_pre)
    u = np.where(shocked, 0.0, -u0)
    p = np.where(shocked, 0.5 * (gamma - 1.0) * rho_post * u0**2, p0)
    return rho, u, p


def noh(x, y, times, gamma: float = 5.0 / 3.0, rho0: float = 1.0, u0: float = 1.0, p0: float = 1e-6,
        case: str = "noh") -> xr.Dataset:
    """The 2D cylindrical Noh implosion (centre at the origin) as a partmesh result Dataset.

    Fields on (time, y, x) from :func:`noh_profile` with geometry "cylindrical"
    (Noh 1987): post-shock density rho0 ((gamma+1)/(gamma-1))^2 (16 for
    gamma = 5/3) behind the shock r < (gamma-1) u0 t/2, at rest with
    e = u0^2/2; ahead of it (u, v) = -u0 (x, y)/r, rho = rho0 (1 + u0 t/r),
    p = ``p0`` (a small nominal pressure; the exact one is 0). At the origin
    itself at t = 0 the velocity is set to 0.
    """
    gamma = ratio_of_heats(gamma)
    rho0, u0, p0 = positive("rho0", rho0), positive("u0", u0), positive("p0", p0)
    x, y = axis("x", x), axis("y", y)
    times = output_times(times)
    xx, yy = np.meshgrid(x, y)
    r = np.hypot(xx, yy)
    with np.errstate(invalid="ignore", divide="ignore"):
        cos, sin = np.where(r > 0.0, xx / r, 0.0), np.where(r > 0.0, yy / r, 0.0)
    rows = [noh_profile(r, t, gamma, rho0, u0, "cylindrical", p0) for t in times]
    rho = np.stack([row[0] for row in rows])
    u_r = np.stack([row[1] for row in rows])
    p = np.stack([row[2] for row in rows])
    return result(
        case=case, method="exact", scheme="Noh implosion, cylindrical (Noh 1987)",
        x=x, y=y, times=times, dx=float(np.mean(np.diff(x))),
        fields={"rho": rho, "u": u_r * cos, "v": u_r * sin, "p": p, "e": internal_energy(p, rho, gamma)},
        parameters={"gamma": gamma, "rho0": rho0, "u0": u0, "p0": p0, "geometry": "cylindrical"},
    )
