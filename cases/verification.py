"""Verification scenes: problems with exact answers (SPEC §4.1)."""

from __future__ import annotations

import numpy as np

from partmesh.cases import checks
from partmesh.cases.disc import disc_density
from partmesh.cases.errors import InputError
from partmesh.cases.scene import Inflow, OutputGrid, Probe, Scene, Wall
from partmesh.cases.shapes import Circle, Polygon
from partmesh.compare import exact, metrics

#: Toro (2009) Table 4.1 states usable through ``sod``'s ``preset``:
#: (left rho, u, p), (right rho, u, p), t_end.
RIEMANN_PRESETS = {
    "sod": ((1.0, 0.0, 1.0), (0.125, 0.0, 0.1), 0.2),
    "toro123": ((1.0, -2.0, 0.4), (1.0, 2.0, 0.4), 0.15),
    "strong_shock": ((1.0, 0.0, 1000.0), (1.0, 0.0, 0.01), 0.012),
}

AIR = {"rho0": 1.225, "p0": 101325.0}


def _uniform(rho, u, v, p):
    """An ``initial`` function giving the same state everywhere."""

    def initial(x, y, dx):
        return rho, u, v, p

    return initial


def sod(preset="sod", left_rho=None, left_u=None, left_p=None, right_rho=None, right_u=None, right_p=None,
        x0=0.5, t_end=None, gamma=1.4, nx_out=400):
    """1D Riemann problem on [0, 1] (Sod 1978; Toro's tests through ``preset``: sod, toro123, strong_shock)."""
    checks.choice("preset", preset, tuple(RIEMANN_PRESETS))
    (lr, lu, lp), (rr, ru, rp), t_default = RIEMANN_PRESETS[preset]
    left = tuple(d if v is None else v for v, d in zip((left_rho, left_u, left_p), (lr, lu, lp)))
    right = tuple(d if v is None else v for v, d in zip((right_rho, right_u, right_p), (rr, ru, rp)))
    for side, state in (("left", left), ("right", right)):
        checks.positive(f"{side}_rho", state[0])
        checks.number(f"{side}_u", state[1])
        checks.positive(f"{side}_p", state[2])
    x0 = checks.in_range("x0", x0, 0.0, 1.0, lo_open=True, hi_open=True)
    t_end = checks.positive("t_end", t_default if t_end is None else t_end)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    nx_out = checks.integer("nx_out", nx_out, 10)

    def initial(x, y, dx):
        is_left = x < x0
        return tuple(np.where(is_left, a, b) for a, b in zip((left[0], left[1], 0.0, left[2]),
                                                              (right[0], right[1], 0.0, right[2])))

    output = OutputGrid(domain=((0.0, 1.0),), shape=(nx_out,), times=(0.5 * t_end, t_end), dt_probe=t_end / 400)
    return Scene(
        name="sod",
        parameters=dict(preset=preset, left_rho=left[0], left_u=left[1], left_p=left[2], right_rho=right[0],
                        right_u=right[1], right_p=right[2], x0=x0, t_end=t_end, gamma=gamma, nx_out=nx_out),
        dim=1, domain=((0.0, 1.0),), gamma=gamma, initial=initial,
        boundaries={"x_lo": "outflow", "x_hi": "outflow"},
        output=output, dx=1.0 / nx_out, t_end=t_end,
        probes=(Probe("mid", x0 + 0.25 * (1.0 - x0)),),
        exact_solution=lambda times: exact.riemann(left, right, output.x, times, x0=x0, gamma=gamma, case="sod"),
        description="Shock tube: a rarefaction, a contact and a shock.",
    )


def shock_reflection(Ms=3.2, rho0=AIR["rho0"], p0=AIR["p0"], length=0.5, height=0.125, dim=1, t_end=None, gamma=1.4):
    """A normal shock of Mach Ms enters a tube at rest and reflects from the end wall."""
    Ms = checks.in_range("Ms", Ms, 1.0, 50.0, lo_open=True)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    length, height = checks.positive("length", length), checks.positive("height", height)
    dim = checks.integer("dim", dim, 1, 2)
    rho1, u1, p1 = exact.normal_shock(Ms, rho0, p0, gamma)
    reflected = exact.reflected_shock(Ms, rho0, p0, gamma)
    a0 = np.sqrt(gamma * p0 / rho0)
    t_hit = length / (Ms * a0)
    t_end = checks.positive("t_end", t_hit + 0.4 * length / reflected["reflected_shock_speed"] if t_end is None else t_end)
    domain = ((0.0, length),) if dim == 1 else ((0.0, length), (0.0, height))
    dx = length / 500
    shape = tuple(int(round((hi - lo) / dx)) for lo, hi in domain)
    boundaries = {"x_lo": Inflow(lambda t, xp=None: (rho1, u1, 0.0, p1), f"post-shock state of a Mach {Ms:g} shock"),
                  "x_hi": "reflect", "y_lo": "reflect", "y_hi": "reflect"}
    probes = (Probe("mid", 0.5 * length, 0.5 * height), Probe("wall", length, 0.5 * height))
    c_r_exact = exact.reflection_coefficient(Ms, gamma)

    def measure(ds):
        """C_R = (p_r − p0)/(p_i − p0) from plateaus: p_i at 'mid' between the
        incident and the reflected shock, p_r at 'wall' after the reflection."""
        t_mid_in = 0.5 * length / (Ms * a0)
        t_back = t_hit + 0.5 * length / reflected["reflected_shock_speed"]
        p_mid = ds["p_probe"].sel(probe="mid")
        p_wall = ds["p_probe"].sel(probe="wall")
        t_last = float(ds["t_probe"][-1])
        if t_last <= t_hit:
            return {}
        p_i = metrics.plateau(p_mid, t_mid_in + 0.3 * (min(t_back, t_last) - t_mid_in), min(t_back, t_last))
        p_r = metrics.plateau(p_wall, t_hit + 0.3 * (t_last - t_hit), t_last)
        return {"reflection_coefficient": (p_r - p0) / (p_i - p0), "reflection_coefficient_exact": c_r_exact}

    return Scene(
        name="shock_reflection",
        parameters=dict(Ms=Ms, rho0=rho0, p0=p0, length=length, height=height, dim=dim, t_end=t_end, gamma=gamma),
        dim=dim, domain=domain, gamma=gamma, initial=_uniform(rho0, 0.0, 0.0, p0),
        boundaries={s: boundaries[s] for s in ("x_lo", "x_hi", "y_lo", "y_hi")[: 2 * dim]},
        output=OutputGrid(domain=domain, shape=shape, times=(0.5 * t_hit, t_hit, t_end), dt_probe=t_end / 2000),
        dx=dx, t_end=t_end, probes=probes, wall=Wall("x_hi", p0, height), measure=measure,
        fields=("rho", "u", "v", "p", "e") if dim == 2 else ("rho", "u", "p", "e"),
        description="Incident and reflected normal shock; measured: C_R against the exact value.",
    )


def wedge(M1=3.5, theta_deg=20.0, rho0=AIR["rho0"], p0=AIR["p0"], x_apex=0.2, t_end=2.5e-3, gamma=1.4):
    """Uniform supersonic flow over a wedge (upper half, symmetry wall below); measured: shock angle."""
    M1 = checks.in_range("M1", M1, 1.0, 20.0, lo_open=True)
    theta = checks.in_range("theta_deg", theta_deg, 0.0, 60.0, lo_open=True, hi_open=True)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    try:
        beta_exact = exact.theta_beta_mach(M1, theta, gamma)
    except ValueError as err:
        raise InputError(f"theta_deg = {theta:g}: {err}") from None
    x_apex = checks.in_range("x_apex", x_apex, 0.05, 0.6)
    t_end = checks.positive("t_end", t_end)
    domain = ((0.0, 1.0), (0.0, 0.75))
    u1 = M1 * np.sqrt(gamma * p0 / rho0)
    run = 1.2
    body = Polygon(((x_apex, 0.0), (x_apex + run, run * np.tan(np.radians(theta))), (x_apex + run, -0.2), (x_apex, -0.2)))

    def measure(ds):
        rho = ds["rho"].isel(time=-1)
        x_hi = min(0.95, x_apex + 0.9 * 0.75 / np.tan(np.radians(beta_exact)))
        angle = metrics.oblique_shock_angle(rho, apex=(x_apex, 0.0), x_range=(x_apex + 0.1, x_hi), rho_free=rho0)
        return {"shock_angle_deg": angle, "shock_angle_exact_deg": beta_exact}

    return Scene(
        name="wedge",
        parameters=dict(M1=M1, theta_deg=theta, rho0=rho0, p0=p0, x_apex=x_apex, t_end=t_end, gamma=gamma),
        dim=2, domain=domain, gamma=gamma, initial=_uniform(rho0, u1, 0.0, p0),
        boundaries={"x_lo": Inflow(lambda t, xp=None: (rho0, u1, 0.0, p0), f"free stream at M1 = {M1:g}"),
                    "x_hi": "outflow", "y_lo": "reflect", "y_hi": "outflow"},
        output=OutputGrid(domain=domain, shape=(400, 300), times=(0.5 * t_end, t_end), dt_probe=t_end / 500),
        dx=2.5e-3, t_end=t_end, obstacles=(body,), probes=(Probe("free", 0.1, 0.7), Probe("ramp", 0.9, 0.6)),
        fields=("rho", "u", "v", "p", "e"), measure=measure,
        description="Attached oblique shock; measured: shock angle against theta-beta-M.",
    )


def sedov(E=1.0, rho0=1.0, p0=1e-5, t_end=0.5, r_init=0.03, half_width=1.0, n_out=256, gamma=1.4):
    """Planar (cylindrical) Sedov–Taylor point blast at the centre of a closed square box."""
    E, rho0, p0 = checks.positive("E", E), checks.positive("rho0", rho0), checks.positive("p0", p0)
    t_end, r_init = checks.positive("t_end", t_end), checks.positive("r_init", r_init)
    L = checks.positive("half_width", half_width)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    n_out = checks.integer("n_out", n_out, 16)
    domain = ((-L, L), (-L, L))

    def initial(x, y, dx):
        """Energy E deposited uniformly over the disc r < max(r_init, 2 dx),
        weighted by each cell's covered fraction (8×8 sub-samples) and
        normalised so the deposited total is exactly E on a lattice of side
        dx with edges on the axes (:func:`~partmesh.cases.disc.disc_density`)."""
        p = p0 + (gamma - 1.0) * E * disc_density(x, y, max(r_init, 2.0 * dx), dx)
        return rho0, 0.0, 0.0, p

    output = OutputGrid(domain=domain, shape=(n_out, n_out), times=(0.0, 0.25 * t_end, 0.5 * t_end, t_end),
                        dt_probe=t_end / 500)
    return Scene(
        name="sedov",
        parameters=dict(E=E, rho0=rho0, p0=p0, t_end=t_end, r_init=r_init, half_width=L, n_out=n_out, gamma=gamma),
        dim=2, domain=domain, gamma=gamma, initial=initial,
        boundaries={s: "reflect" for s in ("x_lo", "x_hi", "y_lo", "y_hi")},
        output=output, dx=2 * L / n_out, t_end=t_end, probes=(Probe("r05", 0.5 * L, 0.0),),
        fields=("rho", "u", "v", "p", "e"),
        exact_solution=lambda times: exact.sedov(E, rho0, p0, output.x, output.y, times, gamma=gamma, case="sedov"),
        description="Cylindrical blast wave; measured: shock radius and profiles against Sedov–Taylor.",
    )


def noh(gamma=5.0 / 3.0, rho0=1.0, u0=1.0, p0=1e-6, t_end=0.6, n_out=200):
    """Noh's cylindrical implosion on the quarter plane [0, 1]² (symmetry walls at x = 0 and y = 0)."""
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    rho0, u0, p0 = checks.positive("rho0", rho0), checks.positive("u0", u0), checks.positive("p0", p0)
    t_end = checks.positive("t_end", t_end)
    n_out = checks.integer("n_out", n_out, 16)
    domain = ((0.0, 1.0), (0.0, 1.0))

    def initial(x, y, dx):
        r = np.hypot(x, y)
        r = np.where(r > 0, r, 1.0)
        return rho0, -u0 * x / r, -u0 * y / r, p0

    output = OutputGrid(domain=domain, shape=(n_out, n_out), times=(0.5 * t_end, t_end), dt_probe=t_end / 300)
    return Scene(
        name="noh",
        parameters=dict(gamma=gamma, rho0=rho0, u0=u0, p0=p0, t_end=t_end, n_out=n_out),
        dim=2, domain=domain, gamma=gamma, initial=initial,
        boundaries={"x_lo": "reflect", "x_hi": "outflow", "y_lo": "reflect", "y_hi": "outflow"},
        output=output, dx=1.0 / n_out, t_end=t_end, probes=(Probe("diag", 0.1, 0.1),),
        fields=("rho", "u", "v", "p", "e"),
        exact_solution=lambda times: exact.noh(output.x, output.y, times, gamma=gamma, rho0=rho0, u0=u0, p0=p0, case="noh"),
        description="Converging cold gas; post-shock density 16 (gamma 5/3), shock speed 1/3.",
    )


def cylinder_shock(Ms=1.16, diameter=0.015, rho0=AIR["rho0"], p0=AIR["p0"], t_end=2.2e-4, gamma=1.4):
    """A Mach 1.16 shock over a cylinder in a channel (qualitative: Mach stems, reflected shocks)."""
    Ms = checks.in_range("Ms", Ms, 1.0, 50.0, lo_open=True)
    d = checks.in_range("diameter", diameter, 1e-4, 0.05)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    t_end = checks.positive("t_end", t_end)
    rho1, u1, p1 = exact.normal_shock(Ms, rho0, p0, gamma)
    domain = ((0.0, 0.12), (0.0, 0.06))
    x_shock = 0.015

    def initial(x, y, dx):
        behind = x < x_shock
        return (np.where(behind, rho1, rho0), np.where(behind, u1, 0.0), 0.0, np.where(behind, p1, p0))

    return Scene(
        name="cylinder_shock",
        parameters=dict(Ms=Ms, diameter=d, rho0=rho0, p0=p0, t_end=t_end, gamma=gamma),
        dim=2, domain=domain, gamma=gamma, initial=initial,
        boundaries={"x_lo": Inflow(lambda t, xp=None: (rho1, u1, 0.0, p1), f"post-shock state of a Mach {Ms:g} shock"),
                    "x_hi": "outflow", "y_lo": "reflect", "y_hi": "reflect"},
        output=OutputGrid(domain=domain, shape=(480, 240), times=(0.5 * t_end, t_end), dt_probe=t_end / 500),
        dx=2.5e-4, t_end=t_end, obstacles=(Circle(0.04, 0.03, 0.5 * d),),
        probes=(Probe("front", 0.03, 0.03), Probe("rear", 0.05, 0.03), Probe("wall", 0.04, 0.06)),
        fields=("rho", "u", "v", "p", "e"),
        description="Shock diffraction over a cylinder (schlieren: triple points, Mach stems).",
    )
