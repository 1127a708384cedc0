"""Scenes of the DSMC study (SPEC §4.2): a planar shock over a square
cavity in a wall, and a burst balloon in a closed box."""

from __future__ import annotations

import numpy as np

from partmesh.cases import checks
from partmesh.cases.scene import OutputGrid, Probe, Scene, Wall
from partmesh.cases.shape_factories import polygon
from partmesh.cases.verification import AIR
from partmesh.compare import exact


def balloon_box(Ms=1.2, radius=0.05, side=0.5, rho0=AIR["rho0"], p0=AIR["p0"], t_end=2e-3, gamma=1.4):
    """A balloon of hot gas (the ambient density, the pressure of the driver
    of a Mach ``Ms`` shock, :func:`partmesh.compare.exact.driver_pressure`) bursts at
    the centre of a closed square box; the shock reflects from the walls and
    focuses in the corners. Measured: the load on the x_hi wall."""
    Ms = checks.in_range("Ms", Ms, 1.0, 5.0, lo_open=True)
    side = checks.positive("side", side)
    radius = checks.in_range("radius", radius, 0.0, 0.4 * side, lo_open=True)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    t_end = checks.positive("t_end", t_end)
    p_balloon = exact.driver_pressure(Ms, rho0, p0, gamma)
    centre = 0.5 * side

    def initial(x, y, dx):
        inside = np.hypot(x - centre, y - centre) < radius
        return rho0, 0.0, 0.0, np.where(inside, p_balloon, p0)

    domain = ((0.0, side), (0.0, side))
    times = tuple(t for t in (0.25e-3, 0.5e-3, 1e-3, 1.5e-3) if t < t_end) + (t_end,)
    return Scene(
        name="balloon_box",
        parameters=dict(Ms=Ms, radius=radius, side=side, rho0=rho0, p0=p0, t_end=t_end, gamma=gamma),
        dim=2, domain=domain, gamma=gamma, initial=initial,
        boundaries={s: "reflect" for s in ("x_lo", "x_hi", "y_lo", "y_hi")},
        output=OutputGrid(domain=domain, shape=(250, 250), times=times, dt_probe=t_end / 1000),
        dx=side / 250, t_end=t_end,
        probes=(Probe("centre", centre, centre), Probe("mid", 0.75 * side, centre), Probe("wall", side, centre),
                Probe("corner", side, side)),
        wall=Wall("x_hi", p0, side), fields=("rho", "u", "v", "p", "e"),
        description=f"A burst balloon (p = {p_balloon / p0:.3f} p0, a Mach {Ms:g} shock) in a closed box.",
    )


def shock_cavity(Ms=1.5, width=0.05, depth=0.05, height=0.1, length=0.3, x_cavity=0.1, rho0=AIR["rho0"],
                 p0=AIR["p0"], t_end=5e-4, gamma=1.4):
    """A planar shock of Mach ``Ms`` runs along a channel of ``height`` over a
    square cavity (``width`` × ``depth``, from ``x_cavity``) cut into its
    floor y = 0: diffraction into the cavity, reflection from its floor and
    walls, the vortex shed at its leading edge. The floor either side of the
    cavity is two blocks running out through the channel's open ends, so the
    shock starts inside the domain with the post-shock gas behind it (an
    inflow side may not carry a solid)."""
    Ms = checks.in_range("Ms", Ms, 1.0, 10.0, lo_open=True)
    width, depth = checks.positive("width", width), checks.positive("depth", depth)
    height, length = checks.positive("height", height), checks.positive("length", length)
    x_cavity = checks.in_range("x_cavity", x_cavity, 0.0, length - width, lo_open=True)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    t_end = checks.positive("t_end", t_end)
    rho1, u1, p1 = exact.normal_shock(Ms, rho0, p0, gamma)
    x_shock = 0.5 * x_cavity
    reach = length  # the blocks run this far beyond the channel's ends
    upstream = polygon([(-reach, -depth), (x_cavity, -depth), (x_cavity, 0.0), (-reach, 0.0)])
    downstream = polygon([(x_cavity + width, -depth), (length + reach, -depth), (length + reach, 0.0),
                          (x_cavity + width, 0.0)])

    def initial(x, y, dx):
        behind = x < x_shock
        return (np.where(behind, rho1, rho0), np.where(behind, u1, 0.0), 0.0, np.where(behind, p1, p0))

    domain = ((0.0, length), (-depth, height))
    n_x = int(round(length / 1e-3))
    return Scene(
        name="shock_cavity",
        parameters=dict(Ms=Ms, width=width, depth=depth, height=height, length=length, x_cavity=x_cavity,
                        rho0=rho0, p0=p0, t_end=t_end, gamma=gamma),
        dim=2, domain=domain, gamma=gamma, initial=initial,
        boundaries={"x_lo": "outflow", "x_hi": "outflow", "y_lo": "reflect", "y_hi": "reflect"},
        output=OutputGrid(domain=domain, shape=(n_x, int(round((height + depth) / 1e-3))),
                          times=(0.25 * t_end, 0.5 * t_end, 0.75 * t_end, t_end), dt_probe=t_end / 1000),
        dx=1e-3, t_end=t_end, obstacles=(upstream, downstream),
        probes=(Probe("cavity_floor", x_cavity + 0.5 * width, -depth), Probe("free", x_cavity + 0.5 * width,
                                                                            0.5 * height),
                Probe("downstream", x_cavity + width + 0.5 * (length - x_cavity - width), 0.0)),
        fields=("rho", "u", "v", "p", "e"),
        description=f"A Mach {Ms:g} shock over a square cavity in a wall (diffraction, reflections, vortex).",
    )
