"""Water scenes (SPEC §4.3): shallow-water verification scenes with exact
answers, for the shallow-water model and the water SPH."""

from __future__ import annotations

import numpy as np

from partmesh.cases import checks
from partmesh.cases.errors import InputError
from partmesh.cases.scene import OutputGrid, Probe, WaterScene
from partmesh.compare import exact, metrics


def dam_break(h_left=1.0, h_right=0.1, length=10.0, x0=5.0, t_end=0.6, nx_out=800, g=9.81, dim=1):
    """Ideal dam break on a flat frictionless bed (Stoker 1957; Ritter 1892 for h_right = 0); ``dim=2``: the
    same dam across a square basin, walls at y = 0 and y = length (the flow stays one-dimensional)."""
    h_left, h_right = checks.positive("h_left", h_left), checks.non_negative("h_right", h_right)
    if not h_right < h_left:
        raise InputError(f"h_right must be below h_left = {h_left:g} m, got {h_right:g} m.")
    length, t_end, g = checks.positive("length", length), checks.positive("t_end", t_end), checks.positive("g", g)
    x0 = checks.in_range("x0", x0, 0.0, length, lo_open=True, hi_open=True)
    nx_out, dim = checks.integer("nx_out", nx_out, 10), checks.integer("dim", dim, 1, 2)
    # the fastest waves (rarefaction head, bore or dry front) must stay inside the domain
    state = exact.dam_break_state(h_left, h_right, g)
    if x0 + state.front_speed * t_end >= length or x0 + state.head_speed * t_end <= 0.0:
        raise InputError(f"t_end = {t_end:g} s lets the waves of the dam break leave [0, {length:g}] m: "
                         f"use t_end <= {min((length - x0) / state.front_speed, -x0 / state.head_speed):.4g} s.")
    domain = ((0.0, length),) * dim
    output = OutputGrid(domain=domain, shape=(nx_out,) * dim, times=(0.5 * t_end, t_end), dt_probe=t_end / 400)

    def exact_solution(times):
        ds = exact.dam_break(output.x, times, h_left, h_right, x0, g, case="dam_break")
        if dim == 1:
            return ds
        across = ds.expand_dims(y=output.y).transpose("time", "y", "x")
        return across.assign_coords(y=("y", output.y, {"units": "m", "long_name": "position y"}))

    mid = 0.5 * length if dim == 2 else 0.0
    return WaterScene(
        name="dam_break",
        parameters=dict(h_left=h_left, h_right=h_right, length=length, x0=x0, t_end=t_end, nx_out=nx_out, g=g,
                        dim=dim),
        dim=dim, domain=domain, depth=max(h_right, h_left), bed=lambda x, y: -h_right + 0.0 * x,
        initial=lambda x, y: (np.where(x < x0, h_left - h_right, 0.0), 0.0, 0.0),
        boundaries={"x_lo": "outflow", "x_hi": "outflow", **({"y_lo": "reflect", "y_hi": "reflect"} if dim == 2 else {})},
        output=output, dx=length / nx_out, t_end=t_end, g=g,
        probes=(Probe("dam", x0, mid), Probe("downstream", x0 + 0.5 * (length - x0), mid)),
        exact_solution=exact_solution,
        description="Dam break; measured: depth against the exact Stoker/Ritter solution.",
    )


def lake_at_rest(dim=1, depth=0.5, island=0.7, ripples=0.1, length=1.0, t_end=0.5, n_out=100, g=9.81):
    """Still water over a bumpy bed with a dry island: it must stay at rest (well-balancing, wet/dry);
    with island = ripples = 0, a hydrostatic tank."""
    dim = checks.integer("dim", dim, 1, 2)
    depth, island = checks.positive("depth", depth), checks.non_negative("island", island)
    ripples = checks.in_range("ripples", ripples, 0.0, 0.5)
    length, t_end, g = checks.positive("length", length), checks.positive("t_end", t_end), checks.positive("g", g)
    n_out = checks.integer("n_out", n_out, 10)
    domain = ((0.0, length),) * dim

    def bed(x, y):
        """A Gaussian island of height ``island`` above the bottom and ripples of ``ripples`` times the depth."""
        r2 = (x - 0.5 * length) ** 2 + (0.0 if y is None else (y - 0.4 * length) ** 2)
        bumps = ripples * depth * np.sin(6.0 * np.pi * x / length) * (1.0 if y is None else np.cos(4.0 * y / length))
        return -depth + island * np.exp(-r2 / (0.02 * length**2)) + bumps

    output = OutputGrid(domain=domain, shape=(n_out,) * dim, times=(t_end,), dt_probe=t_end / 100)
    return WaterScene(
        name="lake_at_rest",
        parameters=dict(dim=dim, depth=depth, island=island, ripples=ripples, length=length, t_end=t_end, n_out=n_out,
                        g=g),
        dim=dim, domain=domain, depth=depth, bed=bed, initial=lambda x, y: (0.0, 0.0, 0.0),
        boundaries={s: "reflect" for s in ("x_lo", "x_hi", "y_lo", "y_hi")[: 2 * dim]},
        output=output, dx=length / n_out, t_end=t_end, g=g,
        probes=(Probe("centre", 0.25 * length, 0.25 * length if dim == 2 else 0.0),),
        description="Lake at rest over a bumpy bed with a dry island; measured: departure from rest.",
    )


def standing_wave(amplitude=0.005, depth=0.5, length=1.0, mode=1, t_end=3.0, nx_out=100, g=9.81):
    """A linear standing wave eta0 = a cos(k x), k = mode pi/length, released at rest in a closed tank."""
    amplitude, depth = checks.positive("amplitude", amplitude), checks.positive("depth", depth)
    length, t_end, g = checks.positive("length", length), checks.positive("t_end", t_end), checks.positive("g", g)
    mode, nx_out = checks.integer("mode", mode, 1), checks.integer("nx_out", nx_out, 10)
    if not amplitude <= 0.1 * depth:
        raise InputError(f"amplitude must be at most a tenth of the depth ({0.1 * depth:g} m) for linear "
                         f"theory to hold, got {amplitude:g} m.")
    k = mode * np.pi / length
    domain = ((0.0, length),)
    output = OutputGrid(domain=domain, shape=(nx_out,), times=tuple(np.linspace(0.0, t_end, 7)[1:]),
                        dt_probe=t_end / 600)
    probes = (Probe("wall", 0.0), Probe("node", 0.5 * length / mode))

    def exact_solution(times):
        return _with_gauges(exact.standing_wave(output.x, times, amplitude, k, depth, g), output, probes, times,
                            lambda x, t: exact.standing_wave_fields(x, t, amplitude, k, depth, g)[0])

    return WaterScene(
        name="standing_wave",
        parameters=dict(amplitude=amplitude, depth=depth, length=length, mode=mode, t_end=t_end, nx_out=nx_out, g=g),
        dim=1, domain=domain, depth=depth, bed=lambda x, y: -depth + 0.0 * x,
        initial=lambda x, y: (amplitude * np.cos(k * x), 0.0, 0.0),
        boundaries={"x_lo": "reflect", "x_hi": "reflect"}, output=output, dx=length / nx_out, t_end=t_end, g=g,
        probes=probes, exact_solution=exact_solution,
        description="Linear standing wave in a closed tank; measured: period and amplitude against linear "
                    "dispersive theory (the shallow-water model gives the non-dispersive period).",
    )


def _with_gauges(ds, output, probes, times, eta_at):
    """The exact Dataset ``ds`` with its gauge records ``eta_probe``, from
    ``eta_at(x, t) -> (t, x)`` at the probes' x over the scene's probe times."""
    t_probe = output.probe_times(float(np.max(times)))
    gauges = np.array([p.x for p in probes], float)
    return ds.assign_coords(probe=[p.name for p in probes], probe_x=("probe", gauges),
                            probe_y=("probe", np.zeros(len(probes))), t_probe=t_probe).assign(
        eta_probe=(("t_probe", "probe"), eta_at(gauges, t_probe),
                   {"units": "m", "long_name": "free-surface elevation at gauge"}))


def first_crests(ds) -> dict:
    """Height, time and arrival of the first crest at every gauge
    (:func:`partmesh.compare.metrics.first_crest`): ``first_crest_height_<gauge>``
    [m], ``first_crest_time_<gauge>`` and ``first_crest_arrival_<gauge>`` [s]."""
    out = {}
    for gauge in ds["probe"].values:
        crest = metrics.first_crest(ds["eta_probe"].sel(probe=gauge))
        out.update({f"first_crest_{what}_{gauge}": value for what, value in crest.items()})
    return out


def _gauge_name(x: float) -> str:
    return f"x{x:g}"


def _linear_wave_scene(name, shape, geometry, depth, length, gauges, t_end, nx_out, g, parameters, description):
    """A wave scene of SPEC §4.3: still water of depth ``depth`` over a flat
    bed, the initial elevation ``shape`` at rest, a reflecting wall (planar)
    or the axis (radial) at x = 0 and an absorbing far end at ``length``; its
    exact solution is linear dispersive theory (:func:`partmesh.compare.exact.linear_waves`),
    fields on the output grid and the series at the gauges."""
    domain = ((0.0, length),)
    n_frames = int(np.ceil(t_end)) + 1
    output = OutputGrid(domain=domain, shape=(nx_out,), times=tuple(np.linspace(0.0, t_end, n_frames)), dt_probe=0.01)
    probes = tuple(Probe(_gauge_name(x), x) for x in gauges)

    def exact_solution(times):
        return _with_gauges(exact.linear_waves(shape, output.x, times, depth, geometry=geometry, g=g, case=name),
                            output, probes, times,
                            lambda x, t: exact.linear_wave_fields(shape, x, t, depth, geometry=geometry, g=g)[0])

    return WaterScene(
        name=name, parameters=parameters, dim=1, domain=domain, depth=depth, bed=lambda x, y: -depth + 0.0 * x,
        initial=lambda x, y: (shape.profile(np.abs(x), geometry), 0.0, 0.0), geometry=geometry,
        boundaries={"x_lo": "axis" if geometry == "radial" else "reflect", "x_hi": "absorbing"},
        output=output, dx=0.01, t_end=t_end, g=g, probes=probes, exact_solution=exact_solution,
        measure=first_crests, description=description,
    )


def prins_mound(Q=0.12, L=0.61, depth=0.7, length=30.0, t_end=10.0, nx_out=1500, g=9.81):
    """Prins' (1958) raised box of water released at rest in a flume; gauges at 2, 4.57, 6 and 8 m."""
    return _prins("prins_mound", Q, L, depth, length, t_end, nx_out, g)


def prins_depression(Q=-0.12, L=0.61, depth=0.7, length=30.0, t_end=10.0, nx_out=1500, g=9.81):
    """Prins' (1958) depressed box of water released at rest in a flume; gauges at 2, 4.57, 6 and 8 m."""
    return _prins("prins_depression", Q, L, depth, length, t_end, nx_out, g)


def _checked_wave_scene(depth, length, t_end, nx_out, g, gauges):
    depth, t_end, g = checks.positive("depth", depth), checks.positive("t_end", t_end), checks.positive("g", g)
    length = checks.positive("length", length)
    nx_out = checks.integer("nx_out", nx_out, 10)
    if not max(gauges) < length:
        raise InputError(f"length must exceed the farthest gauge ({max(gauges):g} m), got {length:g} m.")
    # no wave returns to a gauge from the far end within the run (even were the absorbing end a wall)
    horizon = max(gauges) + np.sqrt(g * depth) * t_end
    if horizon > 2 * length - max(gauges):
        raise InputError(f"length = {length:g} m lets a wave reflected at the far end reach the gauges before "
                         f"t_end = {t_end:g} s: use length >= {0.5 * (horizon + max(gauges)):.4g} m.")
    return depth, length, t_end, nx_out, g


def _prins(name, Q, L, depth, length, t_end, nx_out, g):
    Q, L = checks.number("Q", Q), checks.positive("L", L)
    if Q == 0.0:
        raise InputError("Q must be non-zero (the height of the released box of water).")
    depth, length, t_end, nx_out, g = _checked_wave_scene(depth, length, t_end, nx_out, g, exact.PRINS_GAUGES)
    if not -Q < depth:
        raise InputError(f"Q must be above -depth = {-depth:g} m (water left in the box), got {Q:g} m.")
    return _linear_wave_scene(
        name, exact.Mound(Q, L), "planar", depth, length, exact.PRINS_GAUGES, t_end, nx_out, g,
        dict(Q=Q, L=L, depth=depth, length=length, t_end=t_end, nx_out=nx_out, g=g),
        "Waves from a box of water raised or lowered by Q over 0 <= x <= L, released at rest (Prins 1958); "
        "measured: first crest at each gauge against linear dispersive theory.")


def cavity_collapse(D_c=0.3, R_c=0.6, depth=1.0, geometry="planar", length=25.0, t_end=10.0, nx_out=1250, g=9.81):
    """An explosion cavity with a rim, eta0 = D_c (2 (r/R_c)^2 - 1) for r <= R_c, released at rest; gauges at 2, 4, 6 m."""
    D_c, R_c = checks.positive("D_c", D_c), checks.positive("R_c", R_c)
    geometry = checks.choice("geometry", geometry, ("planar", "radial"))
    depth, length, t_end, nx_out, g = _checked_wave_scene(depth, length, t_end, nx_out, g, exact.CRATER_GAUGES)
    if not D_c < depth:
        raise InputError(f"D_c must be below depth = {depth:g} m (the cavity's floor in the water), got {D_c:g} m.")
    return _linear_wave_scene(
        "cavity_collapse", exact.Crater(D_c, R_c), geometry, depth, length, exact.CRATER_GAUGES, t_end, nx_out, g,
        dict(D_c=D_c, R_c=R_c, depth=depth, geometry=geometry, length=length, t_end=t_end, nx_out=nx_out, g=g),
        "Waves from a collapsing explosion cavity with a rim; measured: first crest at each gauge against linear "
        "dispersive theory.")
