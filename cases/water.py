"""Water scenes (SPEC §4.3): shallow-water verification scenes with exact
answers, for the shallow-water model and the water SPH."""

from __future__ import annotations

import numpy as np

from cases import checks
from cases.registry import scene_builder
from cases.scene import OutputGrid, Probe, WaterScene
from compare import exact


@scene_builder("dam_break")
def dam_break(h_left=1.0, h_right=0.1, length=10.0, x0=5.0, t_end=0.6, nx_out=800, g=9.81):
    """Ideal dam break on a flat frictionless bed (Stoker 1957; Ritter 1892 for h_right = 0)."""
    h_left, h_right = checks.positive("h_left", h_left), checks.non_negative("h_right", h_right)
    if not h_right < h_left:
        raise checks.InputError(f"h_right must be below h_left = {h_left:g} m, got {h_right:g} m.")
    length, t_end, g = checks.positive("length", length), checks.positive("t_end", t_end), checks.positive("g", g)
    x0 = checks.in_range("x0", x0, 0.0, length, lo_open=True, hi_open=True)
    nx_out = checks.integer("nx_out", nx_out, 10)
    # the fastest waves (rarefaction head, bore or dry front) must stay inside the domain
    state = exact.dam_break_state(h_left, h_right, g)
    if x0 + state.front_speed * t_end >= length or x0 + state.head_speed * t_end <= 0.0:
        raise checks.InputError(f"t_end = {t_end:g} s lets the waves of the dam break leave [0, {length:g}] m: "
                                f"use t_end <= {min((length - x0) / state.front_speed, -x0 / state.head_speed):.4g} s.")
    domain = ((0.0, length),)
    output = OutputGrid(domain=domain, shape=(nx_out,), times=(0.5 * t_end, t_end), dt_probe=t_end / 400)
    return WaterScene(
        name="dam_break",
        parameters=dict(h_left=h_left, h_right=h_right, length=length, x0=x0, t_end=t_end, nx_out=nx_out, g=g),
        dim=1, domain=domain, depth=max(h_right, h_left), bed=lambda x, y: -h_right + 0.0 * x,
        initial=lambda x, y: (np.where(x < x0, h_left - h_right, 0.0), 0.0, 0.0),
        boundaries={"x_lo": "outflow", "x_hi": "outflow"}, output=output, dx=length / nx_out, t_end=t_end, g=g,
        probes=(Probe("dam", x0), Probe("downstream", x0 + 0.5 * (length - x0))),
        exact_solution=lambda times: exact.dam_break(output.x, times, h_left, h_right, x0, g, case="dam_break"),
        description="Dam break; measured: depth against the exact Stoker/Ritter solution.",
    )


@scene_builder("lake_at_rest")
def lake_at_rest(dim=1, depth=0.5, island=0.7, length=1.0, t_end=0.5, n_out=100, g=9.81):
    """Still water over a bumpy bed with a dry island: it must stay at rest (well-balancing, wet/dry)."""
    dim = checks.integer("dim", dim, 1, 2)
    depth, island = checks.positive("depth", depth), checks.non_negative("island", island)
    length, t_end, g = checks.positive("length", length), checks.positive("t_end", t_end), checks.positive("g", g)
    n_out = checks.integer("n_out", n_out, 10)
    domain = ((0.0, length),) * dim

    def bed(x, y):
        """A Gaussian island of height ``island`` above the bottom and ripples of a tenth of the depth."""
        r2 = (x - 0.5 * length) ** 2 + (0.0 if y is None else (y - 0.4 * length) ** 2)
        ripples = 0.1 * depth * np.sin(6.0 * np.pi * x / length) * (1.0 if y is None else np.cos(4.0 * y / length))
        return -depth + island * np.exp(-r2 / (0.02 * length**2)) + ripples

    output = OutputGrid(domain=domain, shape=(n_out,) * dim, times=(t_end,), dt_probe=t_end / 100)
    return WaterScene(
        name="lake_at_rest",
        parameters=dict(dim=dim, depth=depth, island=island, length=length, t_end=t_end, n_out=n_out, g=g),
        dim=dim, domain=domain, depth=depth, bed=bed, initial=lambda x, y: (0.0, 0.0, 0.0),
        boundaries={s: "reflect" for s in ("x_lo", "x_hi", "y_lo", "y_hi")[: 2 * dim]},
        output=output, dx=length / n_out, t_end=t_end, g=g,
        probes=(Probe("centre", 0.25 * length, 0.25 * length if dim == 2 else 0.0),),
        description="Lake at rest over a bumpy bed with a dry island; measured: departure from rest.",
    )
