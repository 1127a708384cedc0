"""Blast scenes after Prasanna Kumar, Patnaik & Ramamurthi (Phys. Fluids 30,
046105, 2018): a Friedlander blast enters a channel and loads a rigid wall
(SPEC §4.2)."""

from __future__ import annotations

import numpy as np

from partmesh.cases import checks, shape_factories, shape_queries
from partmesh.cases.disc import disc_density, disc_fraction
from partmesh.cases.errors import InputError
from partmesh.cases.scene import Inflow, OutputGrid, Probe, Scene, Wall
from partmesh.compare import exact, metrics

NEGATIVE_PHASE = ("friedlander", "none")


def blast_inflow(blast, negative_phase, rho0, p0, gamma) -> Inflow:
    """The inflow of a Friedlander blast: overpressure
    ``p_o(t) = p_peak (1 − t/t₊) exp(−α t/t₊)`` mapped to the Rankine–Hugoniot
    post-shock state (ρ, u, p0 + p_o).

    ``negative_phase = "friedlander"`` keeps the formula after t₊ (a weak
    under-pressure, mapped through the same relations, which is an expansion
    with u < 0 to second order); ``"none"`` returns the inflow to the
    ambient state at rest after t₊.
    """
    spec = exact.BLASTS[blast]
    p_peak = spec["p_peak_ratio"] * p0

    def state(t, xp=np):
        p_over = exact.friedlander(t, p_peak, spec["t_plus"], spec["alpha"], negative_phase=negative_phase, xp=xp)
        rho, u, p = exact.rankine_hugoniot_inflow(p_over, rho0, p0, gamma, xp=xp)
        if xp is np:
            return float(rho), float(u), 0.0, float(p)
        return rho, u, 0.0 * rho, p

    return Inflow(state, f"{blast} Friedlander blast (p_peak/p0 = {spec['p_peak_ratio']}, t+ = {spec['t_plus']} s, "
                        f"alpha = {spec['alpha']}), Rankine-Hugoniot state; negative phase: {negative_phase}")


#: the running mean of the wall force [s]: its window spans 20 μs, 21 samples of the scenes' 1 μs probe interval
WALL_MEAN_WINDOW = 2e-5


def wall_load_metrics(ds, p0) -> dict:
    """Peak wall pressure (raw and extrapolated to arrival) and arrival time
    at the wall probe ``w``, peak wall force (raw, extrapolated to its
    arrival the same way: :func:`partmesh.compare.metrics.peak`, and the
    peak of its running mean), and the wall impulse at the final time.

    Arrival (``wall_arrival_time``): the arrival of the transmitted wave,
    the first time the wall overpressure crosses 5 % of its raw peak
    overpressure, linearly interpolated between samples
    (``crossing="first"`` of :func:`partmesh.compare.metrics.arrival_time`).
    Behind an array, and most behind a trap, the wall sees a train of
    waves: the first transmitted wave may decay below 5 % of the peak
    before a later crest, the wave re-reflected inside the array, rises
    higher. The last crossing before the maximum (the metric's default)
    then reads that later crest: the fv square trap of 6 staggered layers
    with a 0.12 m gap read 1.945 ms, 0.16 m 2.257 ms, where the wave
    arrives at 1.470 and 1.488 ms. Ahead of the front a particle record's
    scatter crosses 5 % many times: the crossings before the record's
    running mean (the 21 samples below) last stood at ambient, within its
    scatter, before its peak are passed over (so are the waves of a train
    that returns to ambient before the wave with the peak). On every fv and
    sph run of the blast-array record the arrival so read is the plain
    first crossing (measured); dsmc's is uncertain by its scatter near the
    foot of the front (read on the wall pressure and on the wall force, its
    arrivals differ by 10 μs or less on most runs, by up to 0.13 ms on the
    deep staggered arrays at 2 mm, whose loading rises over 0.1–0.3 ms).

    The fitted peaks read a short fit just after that arrival (2–15 % of
    the positive phase, extrapolated back to it): the raw peaks carry the
    start-up spike of a captured shock reflecting from the wall, which
    grows as the grid is refined (inline circles, fv at 2, 1, 0.5 mm: raw
    peak force 92.6, 96.0, 99.8 kN/m); the fitted peaks read the load just
    after the spike. Following the last crossing before the maximum, the
    fit of the 0.12 m trap sat between the first wave and the later crest
    (1.957–2.157 ms) and read 4.9 kN/m against a raw 23.6. The fit assumes a sharp front: where
    the load rises over much of its window (dsmc's on the deep arrays at
    2 mm, over 0.1–0.3 ms) it reads the rise, not a peak.

    ``wall_force_peak_mean``: the largest centred running mean of the wall
    force over :data:`WALL_MEAN_WINDOW` (20 μs: 21 samples of the 1 μs
    probe interval; :func:`partmesh.compare.metrics.running_peak`). dsmc's
    wall force scatters by about 2 kN/m from sample to sample (lag-one
    correlation 0.2–0.3), so its raw maximum is its largest excursion, on
    the deep arrays at a random late time; the mean of 21 samples scatters
    by about 2/√21 ≈ 0.44 kN/m. The window is chosen from the sampling
    interval and the rise time: it is as long as the rise of dsmc's
    sharpest fronts at 2 mm (10–90 % in 20–30 μs on the 3-layer arrays),
    short against the rise of the deep arrays' loading (100–270 μs), where
    the scatter matters most, and 21 samples long. On a sharp front it
    reads below the raw peak (fv's at 1 mm by 1–13 % on the moderate
    arrays)."""
    p_wall = ds["p_probe"].sel(probe="w")
    samples = _mean_samples(ds["wall_force"])
    peak = _peak_or_nan(p_wall, p0, samples)
    force = _peak_or_nan(ds["wall_force"], 0.0, samples)
    return {
        "wall_peak_pressure_raw": peak["raw"],
        "wall_peak_pressure_fitted": peak["fitted"],
        "wall_arrival_time": peak["arrival"],
        "wall_impulse_final": float(ds["wall_impulse"][-1]),
        "wall_force_peak_raw": force["raw"],
        "wall_force_peak_fitted": force["fitted"],
        "wall_force_peak_mean": _running_peak_or_nan(ds["wall_force"], samples),
    }


def _mean_samples(series) -> int:
    """The odd number of samples that spans :data:`WALL_MEAN_WINDOW` at the
    series' sampling interval (its median step; at least 1)."""
    t = np.asarray(series["t_probe"].values, dtype=float)
    dt = float(np.median(np.diff(t))) if t.size > 1 else WALL_MEAN_WINDOW
    return 2 * int(round(0.5 * WALL_MEAN_WINDOW / dt)) + 1


def _peak_or_nan(series, baseline, samples) -> dict:
    """:func:`partmesh.compare.metrics.peak` of ``series`` with its arrival at
    the first crossing (``samples``: the running mean that passes scatter
    over), or NaN for every value that cannot be read (a run that ends
    before the blast has loaded the wall long enough for the fit: the
    peaks; or before it reaches the wall: the arrival too)."""
    try:
        return metrics.peak(series, baseline=baseline, crossing="first", samples=samples)
    except ValueError:
        pass
    try:  # (the fit refused: the arrival may still be read)
        arrival = metrics.arrival_time(series, baseline, crossing="first", samples=samples)
    except ValueError:
        arrival = float("nan")
    return {"raw": float("nan"), "fitted": float("nan"), "arrival": arrival}


def _running_peak_or_nan(series, samples) -> float:
    """:func:`partmesh.compare.metrics.running_peak` of ``series``, or NaN
    for a record shorter than one window."""
    try:
        return metrics.running_peak(series, samples)["peak"]
    except ValueError:
        return float("nan")


def _checked_blast(blast, negative_phase, rho0, p0, gamma, t_end):
    """The blast settings common to the blast scenes, checked; ``t_end`` defaults to 3 ms (2 ms strong)."""
    checks.choice("blast", blast, tuple(exact.BLASTS))
    checks.choice("negative_phase", negative_phase, NEGATIVE_PHASE)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    t_end = checks.positive("t_end", (3e-3 if blast == "moderate" else 2e-3) if t_end is None else t_end)
    return rho0, p0, gamma, t_end


def _blast_channel(name, parameters, blast, negative_phase, rho0, p0, gamma, domain, height, t_end, obstacles=(),
                   description="", probe_y=None, tiles=1):
    """A blast scene: the blast enters at x = 0 of ``domain``, a rigid wall at
    its far end (periodic across y in 2D), gas at rest (ρ0, p0), 1 mm
    resolution, probes ``u``, ``d`` upstream and downstream at 0.35 and 0.85
    of the length and ``w`` on the wall, at ``probe_y`` (default
    mid-channel; ``height``: the channel's, whose wall the force acts on);
    ``tiles``: see :class:`~partmesh.cases.scene.Scene`."""
    dim, length = len(domain), domain[0][1]
    dx = 1e-3
    shape = tuple(int(round((hi - lo) / dx)) for lo, hi in domain)
    times = tuple(t for t in (0.5e-3, 1.0e-3, 1.5e-3, 1.7e-3, 2.0e-3, 2.5e-3, 3.0e-3) if t < t_end) + (t_end,)
    y_mid = 0.5 * height if probe_y is None else probe_y
    return Scene(
        name=name, parameters=parameters, dim=dim, domain=domain, gamma=gamma,
        initial=lambda x, y, dx: (rho0, 0.0, 0.0, p0),
        boundaries={"x_lo": blast_inflow(blast, negative_phase, rho0, p0, gamma), "x_hi": "reflect",
                    "y_lo": "periodic", "y_hi": "periodic"},
        output=OutputGrid(domain=domain, shape=shape, times=times, dt_probe=1e-6),
        dx=dx, t_end=t_end, obstacles=tuple(obstacles),
        fields=("rho", "u", "v", "p", "e") if dim == 2 else ("rho", "u", "p", "e"),
        probes=(Probe("u", 0.35 * length, y_mid), Probe("d", 0.85 * length, y_mid), Probe("w", length, y_mid)),
        wall=Wall("x_hi", p0, height), measure=lambda ds: wall_load_metrics(ds, p0), description=description,
        tiles=tiles,
    )


def blast_wall(blast="moderate", negative_phase="friedlander", dim=1, rho0=1.0, p0=1.0e5, gamma=1.4,
               length=1.0, height=0.12, t_end=None):
    """A Friedlander blast enters at x = 0 and loads a rigid wall at x = length (no obstacles)."""
    rho0, p0, gamma, t_end = _checked_blast(blast, negative_phase, rho0, p0, gamma, t_end)
    dim = checks.integer("dim", dim, 1, 2)
    length, height = checks.positive("length", length), checks.positive("height", height)
    domain = ((0.0, length),) if dim == 1 else ((0.0, length), (0.0, height))
    return _blast_channel(
        "blast_wall", dict(blast=blast, negative_phase=negative_phase, dim=dim, rho0=rho0, p0=p0, gamma=gamma,
                           length=length, height=height, t_end=t_end),
        blast, negative_phase, rho0, p0, gamma, domain, height, t_end,
        description="Blast loading of a rigid wall; measured: peak wall pressure, arrival time, impulse.")


#: centre-to-centre distance of the rods of a column [m] (SPEC §4.2)
ROW_PITCH = 0.04
ARRANGEMENTS = ("inline", "staggered")


def array_rods(shape, arrangement, rows, layers, column_pitch, size, standoff, trap_gap, length) -> list:
    """The rods of a blast array, column by column from upstream: ``layers``
    columns ``column_pitch`` apart (centre to centre), the downstream face of
    the last one ``standoff`` from the wall at x = ``length``; a
    ``trap_gap`` > 0 moves the upstream half of the columns that much further
    upstream. A column holds ``rows`` rods at y = (k + ½) ``ROW_PITCH``; in a
    ``staggered`` array the second, fourth, ... column from upstream is
    shifted by half a pitch, to y = k ``ROW_PITCH``, and its rods at y = 0
    and y = W = ``rows`` ``ROW_PITCH`` are the two halves of one rod cut by
    the periodic sides (both listed). Every shape has the frontal extent
    ``size`` (:data:`partmesh.cases.shape_factories.SHAPES`), so the blockage is
    ``size/ROW_PITCH`` for all of them."""
    make = shape_factories.SHAPES[shape]
    centres = column_pitch * np.arange(layers, dtype=float)
    centres[: layers // 2] -= trap_gap
    face = make(0.0, 0.0, size).bounds()[2]  # downstream face relative to the centre
    centres += length - standoff - face - centres[-1]
    rods = []
    for c, xc in enumerate(centres):
        shifted = arrangement == "staggered" and c % 2 == 1
        ys = ROW_PITCH * np.arange(rows + 1) if shifted else ROW_PITCH * (np.arange(rows) + 0.5)
        rods += [make(float(xc), float(yc), size) for yc in ys]
    return rods


def blast_array(shape="circle", arrangement="inline", rows=3, layers=3, column_pitch=0.04, size=0.0267,
                standoff=0.34, trap_gap=0.0, blast="moderate", negative_phase="friedlander", rho0=1.0, p0=1.0e5,
                gamma=1.4, length=1.0, t_end=None, one_period=False):
    """The blast of ``blast_wall`` in a channel [0, length] × [0, rows · 0.04 m], periodic in y, loading
    the wall at x = length through an array of rigid rods (SPEC §4.2; :func:`array_rods`).

    ``one_period``: compute one row pitch across y ([0, 0.04 m], one row of rods, the probes at the
    equivalent height (W/2) mod 0.04 m) and tile the result onto the channel: the array repeats every
    row pitch, so this is the same flow at a third of the cost for rows = 3 (a flow that breaks the
    symmetry between rows, which the full channel would allow, is left out)."""
    rho0, p0, gamma, t_end = _checked_blast(blast, negative_phase, rho0, p0, gamma, t_end)
    checks.choice("shape", shape, tuple(shape_factories.SHAPES))
    checks.choice("arrangement", arrangement, ARRANGEMENTS)
    rows, layers = checks.integer("rows", rows, 1), checks.integer("layers", layers, 1)
    length = checks.positive("length", length)
    size = checks.in_range("size", size, 0.0, ROW_PITCH, lo_open=True, hi_open=True)
    column_pitch = checks.positive("column_pitch", column_pitch)
    standoff = checks.in_range("standoff", standoff, 0.0, length, lo_open=True, hi_open=True)
    trap_gap = checks.non_negative("trap_gap", trap_gap)
    one_period = bool(checks.choice("one_period", one_period, (False, True)))
    if trap_gap > 0.0 and layers % 2:
        raise InputError(f"a trap_gap splits the layers into two equal sets: layers must be even, got {layers}.")
    width = ROW_PITCH * rows
    rods = array_rods(shape, arrangement, 1 if one_period else rows, layers, column_pitch, size, standoff, trap_gap,
                      length)
    for k, rod in enumerate(rods):
        if any(shape_queries.overlaps(rod, other) for other in rods[k + 1:]):
            raise InputError(f"column_pitch = {column_pitch:g} m is too small for {shape} rods of size "
                             f"{size:g} m ({arrangement}): neighbouring columns overlap.")
    upstream = min(rod.bounds()[0] for rod in rods)
    if upstream <= 0.35 * length:
        raise InputError(f"the array starts at x = {upstream:.4g} m, upstream of the probe u at "
                         f"{0.35 * length:g} m: use fewer layers, a smaller column_pitch or trap_gap, or a "
                         "smaller standoff.")
    if standoff <= 0.15 * length:
        raise InputError(f"standoff = {standoff:g} m puts the array over the probe d at {0.85 * length:g} m: "
                         f"use standoff > {0.15 * length:g} m.")
    computed = ROW_PITCH if one_period else width
    return _blast_channel(
        "blast_array", dict(shape=shape, arrangement=arrangement, rows=rows, layers=layers,
                            column_pitch=column_pitch, size=size, standoff=standoff, trap_gap=trap_gap, blast=blast,
                            negative_phase=negative_phase, rho0=rho0, p0=p0, gamma=gamma, length=length,
                            t_end=t_end, one_period=one_period),
        blast, negative_phase, rho0, p0, gamma, ((0.0, length), (0.0, computed)), computed, t_end, rods,
        description="Blast loading of a rigid wall behind an array of rods; measured: peak wall pressure and force, "
                    "arrival time, impulse.", probe_y=(0.5 * width) % ROW_PITCH if one_period else None,
        tiles=rows if one_period else 1)


#: energy of one kiloton of TNT [J]
KILOTON = 4.184e12


def blast_kt(kt=1.0, r_c=1.0, rho_c=1000.0, rho0=1.225, p0=1.02e5, gamma=1.4, half_width=None, t_end=1e-3,
             n_out=300):
    """A large planar (cylindrical) explosion in air: a cylinder of radius
    ``r_c`` of dense hot gas (``rho_c``) holding ``kt`` kilotons of TNT per
    metre of depth; one quadrant [0, half_width]² is computed, with
    symmetry walls on the axes and open outer sides, at full size from the
    start. ``half_width`` defaults to 60 m × kt^(1/4), rounded up to 10 m
    (the Sedov–Taylor radius grows as E^(1/4) t^(1/2): the shock of 1 kt
    is at 40 m at 1 ms, and of 10 kt at 72 m in a quadrant of 110 m)."""
    kt, r_c, rho_c = checks.positive("kt", kt), checks.positive("r_c", r_c), checks.positive("rho_c", rho_c)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    if half_width is None:
        half_width = 10.0 * np.ceil(6.0 * kt ** 0.25 - 1e-9)
    L, t_end = checks.positive("half_width", half_width), checks.positive("t_end", t_end)
    n_out = checks.integer("n_out", n_out, 16)
    if not r_c < 0.5 * L:
        raise InputError(f"r_c must be below half of half_width ({0.5 * L:g} m); got {r_c:g} m.")
    energy = kt * KILOTON
    domain = ((0.0, L), (0.0, L))

    def initial(x, y, dx):
        """The cylinder's cells weighted by their covered fraction f (8×8
        sub-samples): density ρ0 + (ρ_c − ρ0) f, and the yield spread over
        the cylinder in proportion to f (:func:`disc_density`), so the
        quadrant holds a quarter of it exactly on a lattice of side dx."""
        rho = rho0 + (rho_c - rho0) * disc_fraction(x, y, r_c, dx)
        p = p0 + (gamma - 1.0) * energy * disc_density(x, y, r_c, dx)
        return rho, 0.0, 0.0, p

    times = tuple(f * t_end for f in (0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0))
    output = OutputGrid(domain=domain, shape=(n_out, n_out), times=times, dt_probe=t_end / 200)
    return Scene(
        name="blast_kt",
        parameters=dict(kt=kt, r_c=r_c, rho_c=rho_c, rho0=rho0, p0=p0, gamma=gamma, half_width=L, t_end=t_end,
                        n_out=n_out),
        dim=2, domain=domain, gamma=gamma, initial=initial,
        boundaries={"x_lo": "reflect", "x_hi": "outflow", "y_lo": "reflect", "y_hi": "outflow"},
        output=output, dx=0.1 * r_c, t_end=t_end,
        probes=tuple(Probe(f"r{f:g}", f * L, 0.0) for f in (0.25, 0.5)),
        fields=("rho", "u", "v", "p", "e"), measure=lambda ds: blast_front(ds, p0),
        description="Large explosion; measured: shock radius and peak density against time (and Sedov-Taylor).",
    )


def blast_front(ds, p0) -> dict:
    """Shock radius (outermost crossing of half the overpressure of the
    outermost wave of the ring-averaged pressure, :func:`partmesh.compare.metrics.shock_radius`
    with ``method="front"``: early on the dense core's gas holds more
    pressure than the air shock ahead of it) and peak ring-averaged density at every
    output time, as lists, and at the last one. The radius is NaN at a
    time the output grid shows no overpressure above ``p0`` (a front still
    inside the first ring of output points)."""
    radii, peaks = [], []
    for k in range(ds.sizes["time"]):
        p, rho = ds.p.isel(time=k), ds.rho.isel(time=k)
        seen = float(metrics.ring_profile(p, centre=(0.0, 0.0))[1].max()) > p0 * (1.0 + 1e-9)
        radii.append(metrics.shock_radius(p, centre=(0.0, 0.0), method="front") if seen else float("nan"))
        peaks.append(float(metrics.ring_profile(rho, centre=(0.0, 0.0))[1].max()))
    return {"shock_radius": radii, "peak_density": peaks, "shock_radius_final": radii[-1],
            "peak_density_final": peaks[-1], "measured_quantities": "shock_radius peak_density"}
