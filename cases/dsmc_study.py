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


def balloon_box_3d(Ms=1.2, diameter=0.075, width=1.78, height=0.46, rho0=AIR["rho0"], p0=AIR["p0"], t_end=1.6e-3,
                   gamma=1.4):
    """The seed's indoor balloon burst in 3D (Sharma & Long 2003, after
    Settles' experiment): a balloon of ``diameter`` at the centre of a closed
    box ``width`` × ``width`` × ``height``, its gas at the ambient density
    and at the temperature behind a Mach ``Ms`` normal shock (so its
    pressure is p0 T_s/T0, 1.128 p0 at Mach 1.2), as the seed derived its
    state. Probes in the X–Y mid-plane at the centres of the x_hi and y_hi
    walls and in their corner, and on the floor under the balloon (the
    nearest wall: the shock reaches it first). The default cell of 1 cm
    divides the box (178 × 178 × 46); ``dx = width/200`` gives dsmc the
    seed's 200 × 200 × 52 cells. By 1.6 ms the shock has met the floor and
    ceiling but not the side walls (about 2.1 ms): a later ``t_end``
    brings it there."""
    Ms = checks.in_range("Ms", Ms, 1.0, 5.0, lo_open=True)
    width, height = checks.positive("width", width), checks.positive("height", height)
    diameter = checks.in_range("diameter", diameter, 0.0, 0.8 * min(width, height), lo_open=True)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    t_end = checks.positive("t_end", t_end)
    rho_s, _, p_s = exact.normal_shock(Ms, rho0, p0, gamma)
    p_balloon = p0 * (p_s / rho_s) / (p0 / rho0)  # the ambient density at the shocked gas's temperature
    centre = (0.5 * width, 0.5 * width, 0.5 * height)

    def initial(x, y, dx, z):
        inside = (x - centre[0]) ** 2 + (y - centre[1]) ** 2 + (z - centre[2]) ** 2 < (0.5 * diameter) ** 2
        return rho0, 0.0, 0.0, 0.0, np.where(inside, p_balloon, p0)

    domain = ((0.0, width), (0.0, width), (0.0, height))
    times = tuple(t for t in (0.54e-3, 1e-3) if t < t_end) + (t_end,)
    mid = centre[2]
    return Scene(
        name="balloon_box_3d",
        parameters=dict(Ms=Ms, diameter=diameter, width=width, height=height, rho0=rho0, p0=p0, t_end=t_end,
                        gamma=gamma),
        dim=3, domain=domain, gamma=gamma, initial=initial,
        boundaries={s: "reflect" for s in ("x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi")},
        output=OutputGrid(domain=domain, shape=(178, 178, 46), times=times, dt_probe=t_end / 400),
        dx=0.01, t_end=t_end,
        probes=(Probe("wall_x", width, centre[1], z=mid), Probe("wall_y", centre[0], width, z=mid),
                Probe("corner", width, width, z=mid), Probe("floor", centre[0], centre[1], z=0.0)),
        fields=("rho", "u", "v", "w", "p", "e"),
        description=f"The seed's balloon burst (p = {p_balloon / p0:.3f} p0, Mach {Ms:g}) in its 3D box.",
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
