"""Verification scenes of a charge of detonation products (SPEC §3.10):
a planar detonation from a rigid wall against its Taylor wave, and a
products–air contact carried at constant speed, whose pressure and velocity
must stay uniform."""

from __future__ import annotations

import numpy as np

from partmesh.cases import checks
from partmesh.cases.errors import InputError
from partmesh.cases.scene import Detonation, OutputGrid, Probe, Scene
from partmesh.compare import exact
from partmesh.compare.materials import TNT

#: sea-level air around the charges
AIR = {"rho0": 1.225, "p0": 101325.0}


def slab_fraction(lo: float, hi: float):
    """``fraction(x, y, dx)`` of a slab ``lo ≤ x ≤ hi``: the exact share of each cell of width dx it covers."""
    def fraction(x, y, dx):
        return np.clip((np.minimum(x + 0.5 * dx, hi) - np.maximum(x - 0.5 * dx, lo)) / dx, 0.0, 1.0)
    return fraction


def initiation_inside(name: str, point: float, lo: float, hi: float) -> float:
    """``point``, refused in one sentence unless it lies in the charge ``[lo, hi]``."""
    point = checks.number(name, point)
    if not lo <= point <= hi:
        raise InputError(f"{name} must lie inside the charge, in [{lo:g}, {hi:g}] m; got {point:g}.")
    return point


def front_position(ds, p_threshold: float) -> np.ndarray:
    """The detonation front at every output time: where p last falls through ``p_threshold``, interpolated
    linearly between the two cells around the crossing (NaN where p never exceeds it)."""
    x = ds.x.values
    out = []
    for row in ds["p"].values:
        above = np.flatnonzero(row > p_threshold)
        if not len(above) or above[-1] + 1 >= len(x):
            out.append(np.nan)
            continue
        i = above[-1]
        out.append(x[i] + (row[i] - p_threshold) / (row[i] - row[i + 1]) * (x[i + 1] - x[i]))
    return np.array(out)


def detonation_1d(length=0.1, air=0.05, t_end=None, initiation=0.0, p0=AIR["p0"], rho_air=AIR["rho0"], gamma=1.4,
                  nx_out=1500):
    """A slab of TNT (:data:`partmesh.compare.materials.TNT`) on ``0 ≤ x ≤ length`` against a rigid wall at
    x = 0, air beyond it, detonated at ``initiation`` (the wall by default): the front runs at the CJ speed,
    the products behind it expand in the Taylor wave (:func:`partmesh.compare.exact.planar_detonation`).
    Default end: the front at 80 % of the slab."""
    length, air = checks.positive("length", length), checks.positive("air", air)
    initiation = initiation_inside("initiation", initiation, 0.0, length)
    p0, rho_air = checks.positive("p0", p0), checks.positive("rho_air", rho_air)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    nx_out = checks.integer("nx_out", nx_out, 10)
    cj = TNT.cj_state()
    t_end = 0.8 * (length - initiation) / cj.D if t_end is None else checks.positive("t_end", t_end)
    domain = ((0.0, length + air),)

    def initial(x, y, dx):
        return rho_air, 0.0, 0.0, p0

    def measure(ds):
        """The front's speed over the last two output times against D, the largest pressure behind it at
        the end against p_CJ, and the pressure's deviation from the Taylor wave between the wall and 95 % of
        the way to the front (its mean relative to p_CJ, its largest relative to the local pressure), where a
        wall initiation has one."""
        times = ds.time.values
        fronts = front_position(ds, 0.5 * cj.p)
        speed = float((fronts[-1] - fronts[-2]) / (times[-1] - times[-2]))
        out = {"front_speed": speed, "front_speed_error": speed / cj.D - 1.0,
               "peak_pressure": float(ds["p"].isel(time=-1).max()), "p_cj": cj.p}
        if initiation == 0.0 and times[-1] * cj.D <= length:
            ref = exact.planar_detonation(TNT, ds.x.values, times[-1:], length, p0)
            behind = ds.x.values < 0.95 * cj.D * times[-1]  # (the last cells before the front: its smearing)
            p_exact = ref["p"].values[-1][behind]
            error = np.abs(ds["p"].values[-1][behind] - p_exact)
            out["taylor_wave_error"] = float(np.mean(error) / cj.p)
            out["taylor_wave_error_max"] = float(np.max(error / p_exact))
        return out

    output = OutputGrid(domain=domain, shape=(nx_out,), times=(0.5 * t_end, 0.75 * t_end, t_end),
                        dt_probe=t_end / 200)
    exact_solution = None
    if initiation == 0.0:
        def exact_solution(times):
            return exact.planar_detonation(TNT, output.x, times, length, p0)
    return Scene(
        name="detonation_1d",
        parameters=dict(length=length, air=air, t_end=t_end, initiation=initiation, p0=p0, rho_air=rho_air,
                        gamma=gamma, nx_out=nx_out),
        dim=1, domain=domain, gamma=gamma, initial=initial,
        boundaries={"x_lo": "reflect", "x_hi": "outflow"}, fields=("rho", "u", "p", "e", "Y"),
        output=output, dx=length / 1000, t_end=t_end, probes=(Probe("mid", 0.5 * length),),
        exact_solution=exact_solution, measure=measure,
        detonation=Detonation(TNT, slab_fraction(0.0, length), (initiation,)),
        description="Planar TNT detonation from a rigid wall; measured: front speed against D, peak pressure "
                    "against p_CJ, the Taylor wave behind the front.",
    )


def products_contact(rho_products=300.0, rho_air=30.0, p=3e8, u=200.0, t_end=None, gamma=1.4, nx_out=200):
    """TNT's detonation products (:data:`partmesh.compare.materials.TNT`, burnt) filling ``0.25 ≤ x ≤ 0.5``
    of a periodic tube of 1 m, air elsewhere, all at pressure ``p`` and velocity ``u``: the two contacts move
    at ``u`` and nothing else happens (SPEC §3.10: the mixture rule keeps pressure equilibrium). At 300 kg/m³
    the products' JWL terms are a large part of their pressure. Default end: the slab has moved one tube
    length."""
    rho_products, rho_air = checks.positive("rho_products", rho_products), checks.positive("rho_air", rho_air)
    p, u = checks.positive("p", p), checks.number("u", u)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    nx_out = checks.integer("nx_out", nx_out, 10)
    t_end = 1.0 / max(abs(u), 1e-300) if t_end is None else checks.positive("t_end", t_end)
    domain = ((0.0, 1.0),)

    def initial(x, y, dx):
        return rho_air, u, 0.0, p

    def measure(ds):
        """The largest relative departure of pressure and velocity from their uniform values over all
        output times, and the width of each contact at the end: the cells whose products' mass fraction lies
        between 1 % and 99 %, per contact."""
        Y = ds["Y"].values[-1]
        return {"pressure_deviation": float(np.max(np.abs(ds["p"].values / p - 1.0))),
                "velocity_deviation": float(np.max(np.abs(ds["u"].values / u - 1.0))) if u else float("nan"),
                "interface_cells": float(np.sum((Y > 0.01) & (Y < 0.99)) / 2.0)}

    output = OutputGrid(domain=domain, shape=(nx_out,), times=(0.5 * t_end, t_end), dt_probe=t_end / 100)
    return Scene(
        name="products_contact",
        parameters=dict(rho_products=rho_products, rho_air=rho_air, p=p, u=u, t_end=t_end, gamma=gamma,
                        nx_out=nx_out),
        dim=1, domain=domain, gamma=gamma, initial=initial,
        boundaries={"x_lo": "periodic", "x_hi": "periodic"}, fields=("rho", "u", "p", "e", "Y"),
        output=output, dx=1.0 / nx_out, t_end=t_end, probes=(Probe("mid", 0.5),), measure=measure,
        detonation=Detonation(TNT, slab_fraction(0.25, 0.5), (0.375,), density=rho_products, burnt=True),
        description="A slab of detonation products in air, carried at constant speed; measured: the pressure's "
                    "and velocity's departures from uniform.",
    )
