"""Verification scenes in three dimensions (SPEC §3.9, §4.1): a shock tube
along any axis of a box, and the spherical Sedov–Taylor blast in a closed
box."""

from __future__ import annotations

import numpy as np

from partmesh.cases import checks
from partmesh.cases.disc import disc_density
from partmesh.cases.scene import OutputGrid, Probe, Scene
from partmesh.cases.verification import RIEMANN_PRESETS
from partmesh.compare import exact, metrics
from partmesh.compare.schema import parameters, result

AXES = ("x", "y", "z")
#: the fields of a 3D scene
FIELDS_3D = ("rho", "u", "v", "w", "p", "e")


def sod_3d(axis="x", preset="sod", width=0.04, t_end=None, gamma=1.4, nx_out=400, ends="reflect"):
    """The 1D Riemann problem of ``sod`` (``preset``: sod, toro123,
    strong_shock; diaphragm at 0.5) in a tube of square cross-section
    ``width`` along ``axis`` of a closed 3D box: its sides slip walls, so
    the flow stays one-dimensional and every method should give its 1D
    result, whichever axis the tube lies along. Its ends are walls too:
    the presets' waves do not reach them by their end times (Sod's
    rarefaction head is at 0.26 and its shock at 0.85 at t = 0.2), so the
    tube holds the unbounded 1D solution (a later ``t_end`` sees them
    reflect). ``ends="outflow"`` opens the tube's two ends instead, as the
    1D ``sod``'s: the waves leave through them."""
    axis = checks.choice("axis", axis, AXES)
    checks.choice("preset", preset, tuple(RIEMANN_PRESETS))
    left, right, t_default = RIEMANN_PRESETS[preset]
    width = checks.in_range("width", width, 0.0, 1.0, lo_open=True)
    t_end = checks.positive("t_end", t_default if t_end is None else t_end)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    nx_out = checks.integer("nx_out", nx_out, 10)
    ends = checks.choice("ends", ends, ("reflect", "outflow"))
    a = AXES.index(axis)
    domain = tuple((0.0, 1.0) if k == a else (0.0, width) for k in range(3))
    x0 = 0.5

    def initial(x, y, dx, z):
        along = (x, y, z)[a]
        rho, u, p = (np.where(along < x0, lo, hi) for lo, hi in zip(left, right))
        velocity = [np.zeros_like(u)] * 3
        velocity[a] = u
        return (rho, *velocity, p)

    output = OutputGrid(domain=domain, shape=tuple(nx_out if k == a else 1 for k in range(3)),
                        times=(0.5 * t_end, t_end), dt_probe=t_end / 400)
    probe = [0.5 * width] * 3
    probe[a] = x0 + 0.25 * (1.0 - x0)

    def exact_solution(times):
        line = exact.riemann(left, right, output.centres(a), times, x0=x0, gamma=gamma, case="sod_3d")
        return along_axis(line, a, output, "sod_3d")

    return Scene(
        name="sod_3d",
        parameters=dict(axis=axis, preset=preset, width=width, t_end=t_end, gamma=gamma, nx_out=nx_out, ends=ends),
        dim=3, domain=domain, gamma=gamma, initial=initial,
        boundaries={side: ends if side[0] == axis else "reflect" for side in ("x_lo", "x_hi", "y_lo", "y_hi",
                                                                                   "z_lo", "z_hi")},
        output=output, dx=1.0 / nx_out, t_end=t_end, probes=(Probe("mid", *probe[:2], z=probe[2]),),
        fields=FIELDS_3D, exact_solution=exact_solution,
        description=f"Shock tube along {axis} of a 3D box: the 1D answer whichever axis it lies along.",
    )


def along_axis(line, a: int, output: OutputGrid, case: str):
    """The 1D schema result ``line`` (on x) laid along axis ``a`` of the 3D
    ``output`` grid (one cell across): its velocity ``u`` becomes the
    component along that axis, the others zero."""
    shape = [1, 1, 1]
    shape[2 - a] = -1  # the layout (z, y, x)
    velocity = {c: np.zeros(line["u"].shape) for c in "uvw"}
    velocity["uvw"[a]] = line["u"].values
    fields = {name: np.reshape(values, (line.time.size, *shape)) for name, values in
              {"rho": line["rho"].values, **velocity, "p": line["p"].values, "e": line["e"].values}.items()}
    return result(case=case, method="exact", scheme=line.attrs["scheme"], x=output.centres(0), y=output.centres(1),
                  z=output.centres(2), times=line.time.values, fields=fields, dx=line.attrs["dx"],
                  parameters={**parameters(line), "axis": "xyz"[a]})


def sedov_3d(E=1.0, rho0=1.0, p0=1e-5, t_end=0.25, r_init=0.03, half_width=1.0, n_out=64, gamma=1.4):
    """The spherical Sedov–Taylor point blast at the centre of a closed
    cube of side 2 ``half_width``: the energy ``E`` deposited evenly over
    the ball of radius ``max(r_init, 2 dx)`` (by each cell's covered
    fraction, normalised so the cells hold E to round-off,
    :func:`~partmesh.cases.disc.disc_density`); measured: the shock radius
    against Sedov–Taylor and its spread over directions
    (:func:`ball_front`)."""
    E, rho0, p0 = checks.positive("E", E), checks.positive("rho0", rho0), checks.positive("p0", p0)
    t_end, r_init = checks.positive("t_end", t_end), checks.positive("r_init", r_init)
    L = checks.positive("half_width", half_width)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    n_out = checks.integer("n_out", n_out, 16)
    domain = ((-L, L),) * 3

    def initial(x, y, dx, z):
        p = p0 + (gamma - 1.0) * E * disc_density(x, y, max(r_init, 2.0 * dx), dx, z)
        return rho0, 0.0, 0.0, 0.0, p

    def measure(ds):
        return ball_front(ds, exact.shock_radius(float(ds.time[-1]), E, rho0, gamma, "spherical"))

    output = OutputGrid(domain=domain, shape=(n_out,) * 3, times=(0.25 * t_end, 0.5 * t_end, t_end),
                        dt_probe=t_end / 500)
    return Scene(
        name="sedov_3d",
        parameters=dict(E=E, rho0=rho0, p0=p0, t_end=t_end, r_init=r_init, half_width=L, n_out=n_out, gamma=gamma),
        dim=3, domain=domain, gamma=gamma, initial=initial,
        boundaries={side: "reflect" for side in ("x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi")},
        output=output, dx=2 * L / n_out, t_end=t_end,
        probes=(Probe("r05_x", 0.5 * L, 0.0), Probe("r05_diagonal", *(0.5 * L / np.sqrt(3.0),) * 2,
                                                     z=0.5 * L / np.sqrt(3.0))),
        fields=FIELDS_3D, measure=measure,
        exact_solution=lambda times: exact.sedov(E, rho0, p0, output.x, output.y, times, gamma=gamma,
                                                 centre=(0.0, 0.0, 0.0), case="sedov_3d", geometry="spherical",
                                                 z=output.z),
        description="Spherical blast wave in a closed box; measured: shock radius and its spread over directions "
                    "against Sedov-Taylor.",
    )


def ball_front(ds, exact_radius: float, sectors: int = 5) -> dict:
    """The radius of a spherical front centred at the origin of a 3D result
    at its final time: over every direction (the half-height crossing of
    the shell-averaged density, :func:`partmesh.compare.metrics.shock_radius`,
    ``method="threshold"``) and per sector of the angle between a direction
    and the nearest grid axis (0° along an axis to 54.7° along a body
    diagonal, in ``sectors`` equal steps), whose spread (max − min over
    their mean) is the grid's imprint on the sphere."""
    rho = ds["rho"].isel(time=-1).transpose("z", "y", "x")
    z, y, x = np.meshgrid(ds.z, ds.y, ds.x, indexing="ij")
    r = np.sqrt(x * x + y * y + z * z)
    with np.errstate(invalid="ignore", divide="ignore"):
        off_axis = np.degrees(np.arccos(np.clip(np.maximum.reduce([abs(x), abs(y), abs(z)]) / r, 0.0, 1.0)))
    edges = np.linspace(0.0, np.degrees(np.arccos(1.0 / np.sqrt(3.0))) + 1e-9, sectors + 1)
    centre = (0.0, 0.0, 0.0)
    per_sector = [metrics.shock_radius(rho.where((off_axis >= lo) & (off_axis < hi)), centre, method="threshold")
                  for lo, hi in zip(edges[:-1], edges[1:])]
    radius = metrics.shock_radius(rho, centre, method="threshold")
    return {"shock_radius": radius, "shock_radius_exact": exact_radius,
            "shock_radius_error": radius / exact_radius - 1.0,
            "shock_radius_spread": (max(per_sector) - min(per_sector)) / float(np.mean(per_sector))}
