"""Free-field charges (SPEC §4.4): the point blast as a sphere, and a TNT
charge on the ground against the Kingery–Bulmash curves, in the r–z plane
of an axisymmetric scene (x is the radius r from the axis, y the height z).

The surface burst models the charge as a Brode balloon (Brode 1959, Phys.
Fluids 2, 217): ideal gas of γ = 1.4 at the charge's density, holding its
detonation energy, released at t = 0; or (``charge="jwl"``) as TNT itself,
detonated from its centre by a programmed burn, its products following the
JWL equation of state (:data:`partmesh.compare.materials.TNT`, SPEC §3.10). A hemisphere on a rigid ground is
half of a sphere of twice the mass in free air, so its flow is spherical:
``surface_burst_1d`` runs that sphere in 1D, and ``surface_burst`` runs the
r–z plane from the 1D solution remapped conservatively
(:func:`partmesh.cases.ball.shells_remapped`) before the shock reaches the
first gauge, where the charge, a few centimetres across, would otherwise
need a grid of millions of cells.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from partmesh.cases import checks
from partmesh.cases.ball import ball_density, shells_remapped
from partmesh.cases.errors import InputError
from partmesh.cases.scene import Detonation, OutputGrid, Precursor, Probe, Scene
from partmesh.compare import exact, materials, metrics
from partmesh.compare.exact.kingery_bulmash import blast_parameters

#: TNT: detonation energy [J/kg] and density [kg/m³] of the Brode balloon
TNT = {"energy": 4.184e6, "density": 1600.0}
#: sea-level air
AIR = {"rho0": 1.225, "p0": 101325.0}
#: the ground gauges, by scaled distance Z = R / W^(1/3) [m/kg^(1/3)]
GAUGES = (0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0, 12.0)
#: the 1D sphere's gauges: out to Z = 20 (Kingery–Bulmash's fits hold from 0.2 to 40)
GAUGES_1D = GAUGES + (20.0,)
#: the domain's extent, in scaled distance
EXTENT = 16.0
#: the 1D sphere's extent, in scaled distance: beyond its outermost gauge
EXTENT_1D = 28.0
#: the charges a surface burst takes: a Brode balloon, or TNT detonated with its products' JWL equation of state
CHARGES = ("balloon", "jwl")
#: when the 1D solution is remapped onto the r–z grid, in scaled time [s/kg^(1/3)]: the shock is at Z ≈ 0.7
T_REMAP = 2.5e-4
#: the cells of the 1D run the r–z grid starts from, across the extent
REMAP_CELLS = 25600
#: the default end time, in scaled time [s/kg^(1/3)]: the gauge Z12's positive phase has ended
T_END = 36e-3
#: the 1D sphere's default end time, in scaled time: the gauge Z20's positive phase has ended (56 ms)
T_END_1D = 60e-3
#: what :func:`gauge_metrics` measures at every gauge
GAUGE_QUANTITIES = ("peak_overpressure", "peak_overpressure_fitted", "arrival_time", "positive_duration",
                    "positive_impulse")


def sedov_spherical(E=1.0, rho0=1.0, p0=1e-5, t_end=0.5, r_init=0.03, half_width=1.0, n_out=256, gamma=1.4):
    """The Sedov–Taylor point blast as a sphere, in one r–z quadrant.

    The axis and the plane z = 0 are symmetry walls and the far sides closed; the energy
    ``E`` of the whole sphere is deposited evenly over the ball of radius
    ``max(r_init, 2 dx)`` (exactly, by each ring cell's share of it), so the
    quadrant holds E/2."""
    E, rho0, p0 = checks.positive("E", E), checks.positive("rho0", rho0), checks.positive("p0", p0)
    t_end, r_init = checks.positive("t_end", t_end), checks.positive("r_init", r_init)
    L = checks.positive("half_width", half_width)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    n_out = checks.integer("n_out", n_out, 16)
    domain = ((0.0, L), (0.0, L))

    def initial(x, y, dx):
        p = p0 + (gamma - 1.0) * E * ball_density(x, y, max(r_init, 2.0 * dx), dx)
        return rho0, 0.0, 0.0, p

    def measure(ds):
        return sphere_front(ds, exact.shock_radius(float(ds.time[-1]), E, rho0, gamma, "spherical"))

    output = OutputGrid(domain=domain, shape=(n_out, n_out), times=(0.25 * t_end, 0.5 * t_end, t_end),
                        dt_probe=t_end / 500)
    return Scene(
        name="sedov_spherical",
        parameters=dict(E=E, rho0=rho0, p0=p0, t_end=t_end, r_init=r_init, half_width=L, n_out=n_out, gamma=gamma),
        dim=2, domain=domain, gamma=gamma, initial=initial, geometry="axisymmetric",
        boundaries={s: "reflect" for s in ("x_lo", "x_hi", "y_lo", "y_hi")},
        output=output, dx=L / n_out, t_end=t_end, probes=(Probe("r05", 0.5 * L, 0.0),),
        fields=("rho", "u", "v", "p", "e"), measure=measure,
        exact_solution=lambda times: exact.sedov(E, rho0, p0, output.x, output.y, times, gamma=gamma,
                                                 case="sedov_spherical", geometry="spherical"),
        description="Spherical blast wave in r-z; measured: shock radius and its spread over polar angle against "
                    "Sedov-Taylor.",
    )


def sphere_front(ds, exact_radius: float, sectors: int = 9) -> dict:
    """The radius of a spherical front centred at the origin of an r–z
    result at its final time: over the whole quadrant (the outermost half-height crossing of the density
    averaged over the cells of each ring of radius, :func:`partmesh.compare.metrics.shock_radius` with
    ``method="threshold"``, which the scatter of a particle method's ambient gas does not reach),
    and per polar-angle sector of ``90°/sectors``, whose spread
    (max − min over the mean) says how spherical the front is."""
    rho = ds["rho"].isel(time=-1)
    angle = np.degrees(np.arctan2(ds.x, ds.y))  # from the axis
    edges = np.linspace(0.0, 90.0, sectors + 1)
    per_sector = [metrics.shock_radius(rho.where((angle >= lo) & (angle < hi)), method="threshold")
                  for lo, hi in zip(edges[:-1], edges[1:])]
    radius = metrics.shock_radius(rho, method="threshold")
    return {"shock_radius": radius, "shock_radius_exact": exact_radius,
            "shock_radius_error": radius / exact_radius - 1.0,
            "shock_radius_spread": (max(per_sector) - min(per_sector)) / float(np.mean(per_sector))}


def _charge(W, rho0, p0, gamma, t_end, charge="balloon", t_default=T_END):
    """The checked charge, air and end time (default ``t_default`` W^(1/3)),
    and the charge's hemisphere radius (of a balloon at TNT's density, or of
    TNT at its unreacted density)."""
    W = checks.in_range("W", W, 1e-3, 1e6)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    checks.choice("charge", charge, CHARGES)
    t_end = t_default * W ** (1.0 / 3.0) if t_end is None else checks.positive("t_end", t_end)
    density = TNT["density"] if charge == "balloon" else materials.TNT.rho0
    return W, rho0, p0, gamma, t_end, (3.0 * W / (2.0 * np.pi * density)) ** (1.0 / 3.0)


def _balloon_pressure(gamma):
    """The Brode balloon's pressure, (γ − 1) ρ_TNT e_TNT [Pa]."""
    return (gamma - 1.0) * TNT["density"] * TNT["energy"]


def _gauges(W, t_end, gauges=GAUGES):
    """The ground gauges, the output times (to ``t_end``) and the probe interval of a charge of ``W`` kg."""
    scale = W ** (1.0 / 3.0)
    probes = tuple(Probe(f"Z{z:g}", z * scale, 0.0, shell=True) for z in gauges)  # (the flow is a hemisphere's)
    times = tuple(t * scale for t in (1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 4e-2) if t * scale < t_end) + (t_end,)
    return probes, times, 5e-6 * scale


def gauge_metrics(ds, W: float, p0: float) -> dict:
    """Per ground gauge ``Z…``: the peak overpressure, raw and fitted (read
    behind the smeared shock and carried back to it by the equal-area rule:
    :func:`partmesh.compare.metrics.shock_fitted_peak`), the arrival time,
    the positive-phase duration and impulse
    (:func:`partmesh.compare.metrics.positive_phase`), each beside its
    Kingery–Bulmash value (``…_kb``, the incident quantities of a
    hemispherical surface burst, Swisdak 1994). NaN where a gauge's record
    cannot be read (no rise above p0); the fitted peak also NaN where the
    record ends inside its positive phase (whose duration and impulse are
    then those up to the end) or the fit is refused (a front too wide to
    fit behind)."""
    out = {}
    for name in ds.probe.values:
        p = ds["p_probe"].sel(probe=name)
        kb = blast_parameters(float(ds.probe_x.sel(probe=name)), W)
        try:
            phase = metrics.positive_phase(p, baseline=p0)
            measured = {"peak_overpressure": float(p.max()) - p0, "arrival_time": phase["arrival"],
                        "positive_duration": phase["duration"], "positive_impulse": phase["impulse"]}
        except ValueError:
            measured = dict.fromkeys(GAUGE_QUANTITIES, float("nan"))
        try:
            measured["peak_overpressure_fitted"] = metrics.shock_fitted_peak(p, baseline=p0)["peak"] - p0
        except ValueError:
            measured["peak_overpressure_fitted"] = float("nan")
        reference = {"peak_overpressure": kb.incident_overpressure, "arrival_time": kb.arrival_time,
                     "positive_duration": kb.positive_duration, "positive_impulse": kb.incident_impulse}
        out.update({f"{name}_{q}": measured[q] for q in GAUGE_QUANTITIES})
        out.update({f"{name}_{q}_kb": float(v) for q, v in reference.items()})
    return out


def surface_burst_1d(W=1.0, rho0=AIR["rho0"], p0=AIR["p0"], gamma=1.4, t_end=None, n_out=2800, dx=None,
                     charge="balloon", extent=EXTENT_1D):
    """The surface burst of ``W`` kg TNT as the sphere it mirrors, in 1D.

    A charge of 2W kg in free air (r from the centre to ``extent`` W^(1/3) m,
    an open far end), with the ground gauges Z0.5 … Z20 at their distances
    (those inside the extent); ``charge`` a Brode balloon or TNT detonated
    from its centre (``"jwl"``); ``n_out`` output cells, ``dx`` the default
    cell size (the output cell when not given). Default end: Z20's positive
    phase over (60 ms W^(1/3))."""
    W, rho0, p0, gamma, t_end, r_c = _charge(W, rho0, p0, gamma, t_end, charge, T_END_1D)
    extent = checks.in_range("extent", extent, 1.0, 1e3)
    L = extent * W ** (1.0 / 3.0)
    n_out = checks.integer("n_out", n_out, 16)
    dx = L / n_out if dx is None else checks.positive("dx", dx)
    p_c = _balloon_pressure(gamma)

    def inside(x, y, cell):
        """The share of each spherical shell cell inside the charge."""
        return np.clip((np.minimum(x + 0.5 * cell, r_c) ** 3 - np.maximum(x - 0.5 * cell, 0.0) ** 3)
                       / ((x + 0.5 * cell) ** 3 - np.maximum(x - 0.5 * cell, 0.0) ** 3), 0.0, 1.0)

    def balloon(x, y, cell):
        share = inside(x, y, cell)
        return (rho0 + share * (TNT["density"] - rho0), 0.0, 0.0, p0 + share * (p_c - p0))

    probes, times, dt_probe = _gauges(W, t_end, tuple(z for z in GAUGES_1D if z < extent))
    jwl = charge == "jwl"
    what = "TNT detonated from its centre, JWL products" if jwl else "Brode balloon"
    return Scene(
        name="surface_burst_1d",
        parameters=dict(W=W, rho0=rho0, p0=p0, gamma=gamma, t_end=t_end, n_out=n_out, dx=dx, charge=charge,
                        extent=extent),
        dim=1, domain=((0.0, L),), gamma=gamma, initial=(lambda x, y, dx: (rho0, 0.0, 0.0, p0)) if jwl else balloon,
        geometry="spherical", boundaries={"x_lo": "reflect", "x_hi": "outflow"},
        output=OutputGrid(domain=((0.0, L),), shape=(n_out,), times=times, dt_probe=dt_probe),
        dx=dx, t_end=t_end, probes=tuple(Probe(pr.name, pr.x) for pr in probes),
        fields=("rho", "u", "p", "e", "Y") if jwl else ("rho", "u", "p", "e"),
        measure=lambda ds: gauge_metrics(ds, W, p0),
        detonation=Detonation(materials.TNT, inside, (0.0,)) if jwl else None,
        description=f"{what} of 2W = {2 * W:g} kg TNT in free air (the sphere a surface burst of W "
                    "mirrors), 1D spherical; measured: the gauges against Kingery-Bulmash.",
    )


def surface_burst(W=1.0, rho0=AIR["rho0"], p0=AIR["p0"], gamma=1.4, t_end=None, n_out=400, start="remap",
                  charge="balloon"):
    """A hemispherical charge of ``W`` kg TNT on a rigid ground, in r–z.

    The charge is a Brode balloon or TNT detonated from its centre
    (``charge="jwl"``, its products with the JWL equation of state), over
    [0, 16 W^(1/3)]² (the axis and the ground reflect, the far sides are
    open), with ground gauges ``Z1`` … ``Z12`` (and ``Z0.5`` when it starts
    from the balloon).
    ``start="remap"`` starts from the 1D spherical fv solution
    (:func:`surface_burst_1d`, 25 600 cells) remapped conserving mass and
    energy at t = 0.25 ms W^(1/3), the shock then at Z ≈ 0.7; ``"balloon"``
    starts from the balloon itself at t = 0 (a few cells across on this grid);
    a TNT charge starts from its 1D sphere."""
    W, rho0, p0, gamma, t_end, r_c = _charge(W, rho0, p0, gamma, t_end, charge)
    checks.choice("start", start, ("remap", "balloon"))
    if charge == "jwl" and start != "remap":
        raise InputError("charge=jwl starts from its 1D sphere, detonated from the centre (start='remap'): a "
                         "charge a few centimetres across would be a handful of cells of the r-z grid.")
    scale = W ** (1.0 / 3.0)
    L = EXTENT * scale
    if start == "remap" and not t_end > T_REMAP * scale:
        raise InputError(f"t_end must be later than {T_REMAP * scale:g} s, when a surface burst of W = {W:g} kg "
                         f"starts from its 1D sphere, got {t_end:g} s (start='balloon' starts at 0).")
    n_out = checks.integer("n_out", n_out, 16)
    domain = ((0.0, L), (0.0, L))
    # (a start from the 1D sphere begins with its shock past Z = 0.7: the gauges inside it are left out)
    probes, times, dt_probe = _gauges(W, t_end, tuple(z for z in GAUGES if start == "balloon" or z >= 1.0))
    p_c = _balloon_pressure(gamma)
    sphere_volume = (4.0 / 3.0) * np.pi * r_c ** 3

    def balloon(x, y, dx):
        inside = ball_density(x, y, r_c, dx) * sphere_volume  # the fraction of each ring cell in the charge
        return (rho0 + inside * (TNT["density"] - rho0), 0.0, 0.0, p0 + inside * (p_c - p0))

    parameters = dict(W=W, rho0=rho0, p0=p0, gamma=gamma, t_end=t_end, n_out=n_out, start=start, charge=charge)
    scene = Scene(
        name="surface_burst", parameters=parameters, dim=2, domain=domain, gamma=gamma, initial=balloon,
        geometry="axisymmetric",
        boundaries={"x_lo": "reflect", "x_hi": "outflow", "y_lo": "reflect", "y_hi": "outflow"},
        output=OutputGrid(domain=domain, shape=(n_out, n_out), times=times, dt_probe=dt_probe),
        dx=L / 800, t_end=t_end, probes=probes,
        fields=("rho", "u", "v", "p", "e", "Y") if charge == "jwl" else ("rho", "u", "v", "p", "e"),
        measure=lambda ds: gauge_metrics(ds, W, p0),
        description=f"Hemispherical TNT surface burst ({'JWL products' if charge == 'jwl' else 'Brode balloon'}) "
                    "in r-z; measured: peak overpressure, arrival, positive duration and impulse at the ground "
                    "gauges against Kingery-Bulmash.",
    )
    if start == "balloon":
        return scene
    t_remap = T_REMAP * scale
    sphere = surface_burst_1d(W, rho0, p0, gamma, t_end=t_remap, n_out=REMAP_CELLS, charge=charge, extent=EXTENT)
    if charge == "jwl":  # (the remap carries the products' volume)
        sphere = dataclasses.replace(sphere, fields=sphere.fields + ("alpha",))
    return dataclasses.replace(scene, precursor=Precursor(sphere, "fv", {"dx": L / REMAP_CELLS},
                                                         lambda ds: remapped(scene, ds)))


def remapped(scene: Scene, sphere) -> Scene:
    """``scene`` starting from the last frame of the 1D spherical result
    ``sphere`` (on its solver's cells), remapped onto the r–z cells by the
    overlap of every ring cell with every spherical shell
    (:func:`partmesh.cases.ball.shells_remapped`): each cell's mass,
    momentum and energy are what the shells it covers held, so the grid
    holds the sphere's half to round-off; the radial momentum is split
    into r and z by the direction of each cell's centre. A sphere of
    detonation products (fields ``Y`` and ``alpha``) also brings the products'
    mass and volume of every shell, and each cell's pressure is the mixture's
    (:class:`partmesh.compare.materials.ProductsInAir`)."""
    gamma = scene.gamma
    last = sphere.isel(time=-1)
    rho, u, p = (np.asarray(last[f].values, float) for f in ("rho", "u", "p"))
    x = np.asarray(sphere.x.values, float)
    edges = np.concatenate([[0.0], 0.5 * (x[1:] + x[:-1]), [x[-1] + 0.5 * (x[-1] - x[-2])]])
    ambient = scene.parameters["rho0"], scene.parameters["p0"]
    products = "Y" in sphere
    internal = rho * np.asarray(last["e"].values, float) if products else p / (gamma - 1.0)
    moments = {"mass": rho, "momentum": rho * u, "energy": internal + 0.5 * rho * u * u}
    outside = {"mass": ambient[0], "momentum": 0.0, "energy": ambient[1] / (gamma - 1.0)}
    if products:
        moments.update(products=rho * np.asarray(last["Y"].values, float), volume=np.asarray(last["alpha"].values))
        outside.update(products=0.0, volume=0.0)
    t_start = float(sphere.time[-1])
    mixture = materials.ProductsInAir(materials.TNT, gamma)
    kept = {}

    def state(r, z, dx):
        """``(ρ, u_r, u_z, p, ρY, α)`` of the ring cells (computed once per grid)."""
        key = (float(dx), np.shape(r), float(np.sum(r)), float(np.sum(z)))
        if key not in kept:
            mean = {k: shells_remapped(r, z, dx, edges, v, outside[k]) for k, v in moments.items()}
            R = np.hypot(r, z)
            direction = np.where(R > 0.0, 1.0 / np.where(R > 0.0, R, 1.0), 0.0)
            rho_c = mean["mass"]
            u_r, u_z = mean["momentum"] * r * direction / rho_c, mean["momentum"] * z * direction / rho_c
            rho_e = mean["energy"] - 0.5 * rho_c * (u_r * u_r + u_z * u_z)
            kept.clear()
            if not products:
                kept[key] = (rho_c, u_r, u_z, (gamma - 1.0) * rho_e, None, None)
            else:
                # (a cell without air mass is products only: its volume fraction, advected apart from the
                # masses, may fall short of 1 by rounding, ~1e-11, which would leave air of zero density)
                rho_y = mean["products"]
                alpha = np.where(rho_c > rho_y, np.clip(mean["volume"], 0.0, 1.0), 1.0)
                kept[key] = (rho_c, u_r, u_z, mixture.pressure(rho_c, (rho_y, rho_y, alpha), rho_e), rho_y, alpha)
        return kept[key]

    def initial(r, z, dx):
        rho_c, u_r, u_z, p_c, rho_y, alpha = state(r, z, dx)
        if products:  # (the air's density: the products' share is the charge's)
            rho_c = np.where(alpha < 1.0, (rho_c - rho_y) / np.where(alpha < 1.0, 1.0 - alpha, 1.0), ambient[0])
        return rho_c, u_r, u_z, p_c

    def products_density(r, z, dx):
        _, _, _, _, rho_y, alpha = state(r, z, dx)
        return np.where(alpha > 0.0, rho_y / np.where(alpha > 0.0, alpha, 1.0), materials.TNT.rho0)

    note = (f"started at t = {t_start:.6g} s from the 1D spherical fv run surface_burst_1d on {x.size} cells "
            "remapped onto the r-z cells by their exact overlap with its shells (mass, momentum magnitude and "
            f"energy{', products mass and volume' if products else ''} of every shell kept)")
    detonation = None if not products else Detonation(materials.TNT, lambda r, z, dx: state(r, z, dx)[5], (0.0, 0.0),
                                                      density=products_density, burnt=True)
    return dataclasses.replace(scene, initial=initial, t_start=t_start, precursor=None, detonation=detonation,
                               parameters={**scene.parameters, "started_from": note},
                               description=f"{scene.description} {note[0].upper()}{note[1:]}.")
