"""Sedov-Taylor point blast in a uniform gas at zero counter-pressure.

The closed-form self-similar solution of L. I. Sedov (*Similarity and
Dimensional Methods in Mechanics*, 1959, ch. IV), in the form of
J. R. Kamm & F. X. Timmes, "On efficient generation of numerically robust
Sedov solutions", LA-UR-07-2849 (2007), with density exponent omega = 0
(uniform density): the "standard" case, plus the removable singular case
gamma = 2 (omega = omega_3 = j(2 - gamma); D. Book, Shock Waves 4, 1, 1994).
Geometry j = 1 (planar), 2 (cylindrical), 3 (spherical); any gamma > 1
(gamma < 7 in spherical geometry, beyond which the solution has a vacuum
core, which is not implemented).

Energy convention, E = alpha rho0 R^(j+2) / t^2 with R the shock radius:
planar, E per unit area of the symmetry plane for the whole slab -R < x < R
(both sides; alpha = 1.077486 for gamma = 1.4, twice the half-space value
0.538743); cylindrical, E per unit length of the axis (alpha = 0.984074);
spherical, the total energy (alpha = 0.851072). Kamm & Timmes (2007, Table 4)
print 0.538548 (half-space), 0.984041 and 0.851072; the first two are low by
3.6e-4 and 3.4e-5 relative against both this closed form and a direct
integration of Sedov's ODEs, which agree to 1e-12.

The similarity variable V runs from V0 = 2/((j+2) gamma) at the centre to
V2 = 4/((j+2)(gamma+1)) at the shock. This module parametrises it as
V = V0 + (V2 - V0) s^m with m = (2(gamma-1) + j)/(gamma-1), which makes
lambda = r/R proportional to s near the centre, so lambda(s) is smooth, the
energy integral is a regular quadrature in s, and r -> s is a
well-conditioned Newton solve in ln s.
"""

from __future__ import annotations

from functools import lru_cache, reduce
from typing import NamedTuple

import numpy as np
import xarray as xr

from partmesh.compare.exact._inputs import (
    axis,
    geometry_index,
    internal_energy,
    output_times,
    positive,
    ratio_of_heats,
)
from partmesh.compare.schema import result

#: |gamma - 2| below which the singular (gamma = 2) closed form is used
SINGULAR_BAND = 1e-8
#: the area (j = 1, both sides), circumference (j = 2) or sphere area (j = 3) factor of dV = sigma r^(j-1) dr
SIGMA = {1: 2.0, 2: 2.0 * np.pi, 3: 4.0 * np.pi}


class _Sedov(NamedTuple):
    """Constants of the closed form (Kamm & Timmes 2007, omega = 0)."""

    j: int
    gamma: float
    a0: float
    a1: float
    a2: float
    a3: float
    a4: float
    a5: float
    a: float
    b: float
    c: float
    d: float
    e: float
    v0: float
    width: float  # V2 - V0
    m: float      # exponent of s in V - V0
    lam0: float   # ln of the constant factor (b c (V2 - V0))^(-a2) of lambda/s, from x2^(-a2)
    singular: bool


@lru_cache(maxsize=64)
def _constants(gamma: float, j: int) -> _Sedov:
    xg2 = j + 2.0
    denom2 = 2.0 * (gamma - 1.0) + j
    denom3 = j * (2.0 - gamma)
    a2 = -(gamma - 1.0) / denom2
    a1 = xg2 * gamma / (2.0 + j * (gamma - 1.0)) * (2.0 * j * (2.0 - gamma) / (gamma * xg2**2) - a2)
    singular = abs(gamma - 2.0) < SINGULAR_BAND
    a4, a5 = (np.nan, np.nan) if singular else (xg2 * j * a1 / denom3, -2.0 * j / denom3)
    b, c = (gamma + 1.0) / (gamma - 1.0), 0.5 * xg2 * gamma
    v0, v2 = 2.0 / (xg2 * gamma), 4.0 / (xg2 * (gamma + 1.0))
    return _Sedov(
        j=j, gamma=gamma, a0=2.0 / xg2, a1=a1, a2=a2, a3=j / denom2, a4=a4, a5=a5,
        a=0.25 * xg2 * (gamma + 1.0), b=b, c=c,
        d=xg2 * (gamma + 1.0) / (xg2 * (gamma + 1.0) - 2.0 * (2.0 + j * (gamma - 1.0))),
        e=0.5 * (2.0 + j * (gamma - 1.0)),
        v0=v0, width=v2 - v0, m=-1.0 / a2, lam0=-a2 * np.log(b * c * (v2 - v0)), singular=singular,
    )


def _similarity(k: _Sedov, s):
    """lambda, lambda/s, d ln(lambda)/d ln(s), f, g, h at parameter s in [0, 1]
    (Kamm & Timmes 2007; the singular case gamma = 2 from Book 1994)."""
    s = np.asarray(s, dtype=float)
    sm = s**k.m
    v = k.v0 + k.width * sm
    x1 = k.a * v
    x3 = k.d * (1.0 - k.e * v)
    x4 = k.b * (1.0 - 0.5 * (k.j + 2.0) * v)
    lam_over_s = np.exp(k.lam0 - k.a0 * np.log(x1) - k.a1 * np.log(x3))
    lam = s * lam_over_s
    dlog = 1.0 + k.m * k.width * sm * (-k.a0 * k.a / x1 + k.a1 * k.d * k.e / x3)
    x2_a3 = (k.b * k.c * k.width) ** k.a3 * s ** (k.m * k.a3)  # x2^a3, x2 = b (c V - 1) = b c (V2 - V0) s^m
    if k.singular:
        beta0 = 1.0 / (2.0 * k.e)
        gp1 = k.gamma + 1.0
        core = np.exp(-k.j * k.gamma * gp1 * beta0 * (1.0 - x1) / (0.5 * gp1 - x1))
        g = x2_a3 * x4 ** (1.0 - 4.0 * beta0) * core
        h = x1 ** (k.a0 * k.j) * x4 ** (2.0 * (k.j * (k.gamma - 1.0) - k.gamma) * beta0) * core
    else:  # in logs: a4 and a5 grow like 1/(2 - gamma) while x3^a4 x4^a5 stays finite
        log_x3, log_x4 = np.log(x3), np.log(x4)
        g = x2_a3 * np.exp(k.a4 * log_x3 + k.a5 * log_x4)
        h = x1 ** (k.a0 * k.j) * np.exp((k.a4 - 2.0 * k.a1) * log_x3 + (1.0 + k.a5) * log_x4)
    return lam, lam_over_s, dlog, x1 * lam, g, h


@lru_cache(maxsize=64)
def _alpha(gamma: float, j: int) -> float:
    """alpha = sigma_j 8/((gamma+1)(gamma-1)(j+2)^2) int_0^1 (f^2 g + h) lambda^(j-1) d lambda."""
    from scipy.integrate import quad  # (SciPy loads with the first Sedov energy integral)

    k = _constants(gamma, j)

    def integrand(s):
        lam, lam_over_s, dlog, f, g, h = _similarity(k, s)
        return (f * f * g + h) * lam ** (j - 1) * lam_over_s * dlog  # (f^2 g + h) lambda^(j-1) d lambda/ds

    integral = quad(integrand, 0.0, 1.0, epsabs=0.0, epsrel=1e-13, limit=200)[0]
    return SIGMA[j] * 8.0 / ((gamma + 1.0) * (gamma - 1.0) * (j + 2.0) ** 2) * integral


def _check_gamma(gamma, j: int) -> float:
    gamma = ratio_of_heats(gamma)
    if j == 3 and gamma >= 7.0:
        raise ValueError(f"gamma must be in (1, 7) for a spherical Sedov blast (the standard case), got {gamma}.")
    return gamma


def sedov_alpha(gamma: float = 1.4, geometry: str = "cylindrical") -> float:
    """The energy constant alpha of E = alpha rho0 R^(j+2)/t^2 (Kamm & Timmes 2007).

    alpha = sigma_j 8/((gamma+1)(gamma-1)(j+2)^2) int_0^1 (f^2 g + h) lambda^(j-1) d lambda,
    sigma = 2, 2 pi, 4 pi for j = 1, 2, 3, with f, g, h the reduced velocity,
    density and pressure of the closed form; computed by adaptive quadrature
    (relative tolerance 1e-13). E is per unit area (planar, whole slab), per
    unit length (cylindrical) or total (spherical).
    """
    j = geometry_index(geometry)
    return _alpha(_check_gamma(gamma, j), j)


def shock_radius(t, E, rho0, gamma: float = 1.4, geometry: str = "cylindrical"):
    """Sedov-Taylor shock radius R(t) = (E t^2/(alpha rho0))^(1/(j+2)) (Sedov 1959; Kamm & Timmes 2007).

    ``E`` per unit area (planar), per unit length (cylindrical) or total
    (spherical); alpha from :func:`sedov_alpha`. Vectorised over ``t`` (>= 0).
    """
    j = geometry_index(geometry)
    alpha = _alpha(_check_gamma(gamma, j), j)
    E, rho0 = positive("E", E), positive("rho0", rho0)
    t = np.asarray(t, dtype=float)
    if not np.all(np.isfinite(t)) or np.any(t < 0.0):
        raise ValueError("t must be finite and >= 0.")
    return (E * t * t / (alpha * rho0)) ** (1.0 / (j + 2.0))


def _parameter_of(k: _Sedov, lam):
    """s in (0, 1] with lambda(s) = lam, by Newton iteration on ln s (lam in (0, 1])."""
    target = np.log(lam)
    sigma = np.minimum(target - k.lam0 + k.a0 * np.log(k.a * k.v0) + k.a1 * np.log(k.d * (1.0 - k.e * k.v0)), 0.0)
    for _ in range(50):
        lam_s, _, dlog, *_ = _similarity(k, np.exp(sigma))
        step = (np.log(lam_s) - target) / dlog
        sigma = np.minimum(sigma - step, 0.0)
        if np.all(np.abs(step) <= 1e-14):
            return np.exp(sigma)
    raise RuntimeError("the Newton iteration for the Sedov similarity variable did not converge.")


def sedov_profile(r, t, E, rho0, gamma: float = 1.4, geometry: str = "cylindrical"):
    """Density, radial velocity and pressure (rho, u, p) of the Sedov-Taylor blast at radius ``r``, time ``t``.

    Self-similar solution (Sedov 1959; Kamm & Timmes 2007):
    with R = shock_radius(t), lambda = r/R, shock speed U = 2R/((j+2) t) and the
    strong-shock values rho2 = rho0 (gamma+1)/(gamma-1), u2 = 2U/(gamma+1),
    p2 = 2 rho0 U^2/(gamma+1), the solution for r <= R is rho = rho2 g,
    u = u2 f, p = p2 h, where lambda = x1^-a0 x2^-a2 x3^-a1, f = x1 lambda,
    g = x2^a3 x3^a4 x4^a5, h = x1^(a0 j) x3^(a4-2a1) x4^(1+a5) are given in
    parametric form over V in [V0, V2] (x1 = aV, x2 = b(cV-1), x3 = d(1-eV),
    x4 = b(1 - (j+2)V/2)). Ahead of the shock (r > R): rho0, 0, 0 (zero
    counter-pressure). At r = 0, rho = 0 and p is finite.

    ``E`` per unit area (planar, whole slab), per unit length (cylindrical) or
    total (spherical); ``t`` > 0; vectorised over ``r`` (>= 0).
    """
    j = geometry_index(geometry)
    gamma = _check_gamma(gamma, j)
    t = positive("t", t)
    radius = shock_radius(t, E, rho0, gamma, geometry)
    r = np.asarray(r, dtype=float)
    if not np.all(np.isfinite(r)) or np.any(r < 0.0):
        raise ValueError("r must be finite and >= 0.")
    k = _constants(gamma, j)
    lam = r / radius
    inside = (lam > 0.0) & (lam <= 1.0)
    s = np.zeros_like(lam)
    s[inside] = _parameter_of(k, lam[inside])
    _, _, _, f, g, h = _similarity(k, s)
    speed = 2.0 * radius / ((j + 2.0) * t)
    rho = np.where(lam <= 1.0, rho0 * k.b * g, rho0)
    u = np.where(lam <= 1.0, 2.0 * speed / (gamma + 1.0) * f, 0.0)
    p = np.where(lam <= 1.0, 2.0 * rho0 * speed**2 / (gamma + 1.0) * h, 0.0)
    return rho, u, p


def sedov(E, rho0, p0, x, y, times, gamma: float = 1.4, centre=(0.0, 0.0), case: str = "sedov",
          geometry: str = "cylindrical", z=None) -> xr.Dataset:
    """The Sedov-Taylor blast on a 2D or 3D grid, as a partmesh result Dataset.

    Fields on (time, y, x) from :func:`sedov_profile` with ``geometry``
    "cylindrical" (a planar grid, E per unit length, Kamm & Timmes 2007) or
    "spherical" (an axisymmetric grid, x the radius from the axis and y
    along it, E the whole sphere's) about ``centre``; with ``z``, on
    (time, z, y, x) of a 3D grid ("spherical", ``centre`` (xc, yc, zc)):
    the velocity is u_r (x − x_c)/r along each axis; p = max(p_sedov, p0), so the gas
    ahead of the shock is at rho0, p0 and rest (the blast solution itself
    assumes p0 << p behind the shock); e = p/((gamma-1) rho), which is
    infinite at a grid point exactly at the centre (rho = 0 there).
    ``times`` > 0 (the point blast is singular at t = 0).
    """
    E, rho0, p0 = positive("E", E), positive("rho0", rho0), positive("p0", p0)
    if geometry not in ("cylindrical", "spherical") or (z is not None and geometry != "spherical"):
        raise ValueError(f"geometry must be 'cylindrical' or 'spherical' on a 2D grid and 'spherical' on a 3D grid, "
                         f"got {geometry!r}.")
    j = geometry_index(geometry)
    gamma = _check_gamma(gamma, j)
    coords = [axis("x", x), axis("y", y)] + ([] if z is None else [axis("z", z)])
    if len(centre) != len(coords):
        raise ValueError(f"centre must have {len(coords)} coordinates on a {len(coords)}D grid, got {len(centre)}.")
    times = output_times(times, allow_zero=False)
    centre = [float(c) for c in centre]
    # the offsets from the centre along x, y (, z), laid out ([z,] y, x)
    offsets = np.meshgrid(*(c - cc for c, cc in zip(coords[::-1], centre[::-1])), indexing="ij")[::-1]
    r = reduce(np.hypot, offsets)
    with np.errstate(invalid="ignore", divide="ignore"):
        directions = [np.where(r > 0.0, o / r, 0.0) for o in offsets]
    rows = [sedov_profile(r, t, E, rho0, gamma, geometry) for t in times]
    rho = np.stack([row[0] for row in rows])
    u_r = np.stack([row[1] for row in rows])
    p = np.maximum(np.stack([row[2] for row in rows]), p0)
    return result(
        case=case, method="exact", scheme=f"Sedov-Taylor blast, {geometry} (Kamm & Timmes 2007 closed form)",
        x=coords[0], y=coords[1], z=z if z is None else coords[2], times=times, dx=float(np.mean(np.diff(coords[0]))),
        fields={"rho": rho, **{c: u_r * n for c, n in zip("uvw", directions)}, "p": p,
                "e": internal_energy(p, rho, gamma)},
        parameters={"E": E, "rho0": rho0, "p0": p0, "gamma": gamma, "centre": centre,
                    "geometry": geometry, "alpha": _alpha(gamma, j)},
        geometry="axisymmetric" if j == 3 and z is None else "planar",
    )
