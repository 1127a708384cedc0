"""Blast scenes after Prasanna Kumar, Patnaik & Ramamurthi (Phys. Fluids 30,
046105, 2018): a Friedlander blast enters a channel and loads a rigid wall
(SPEC §4.2)."""

from __future__ import annotations

from cases import checks
from cases.registry import scene_builder
from cases.scene import Inflow, OutputGrid, Probe, Scene, Wall
from compare import exact, metrics

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

    def state(t):
        p_over = exact.friedlander(t, p_peak, spec["t_plus"], spec["alpha"], negative_phase=negative_phase)
        rho, u, p = exact.rankine_hugoniot_inflow(p_over, rho0, p0, gamma)
        return float(rho), float(u), 0.0, float(p)

    return Inflow(state, f"{blast} Friedlander blast (p_peak/p0 = {spec['p_peak_ratio']}, t+ = {spec['t_plus']} s, "
                        f"alpha = {spec['alpha']}), Rankine-Hugoniot state; negative phase: {negative_phase}")


def wall_load_metrics(ds, p0) -> dict:
    """Peak wall pressure (raw and extrapolated to arrival), arrival time, and
    the wall impulse at the final time, from the wall probe ``w``."""
    p_wall = ds["p_probe"].sel(probe="w")
    peak = metrics.peak(p_wall, baseline=p0)
    return {
        "wall_peak_pressure_raw": peak["raw"],
        "wall_peak_pressure_fitted": peak["fitted"],
        "wall_arrival_time": peak["arrival"],
        "wall_impulse_final": float(ds["wall_impulse"][-1]),
        "wall_force_peak": float(ds["wall_force"].max()),
    }


@scene_builder("blast_wall")
def blast_wall(blast="moderate", negative_phase="friedlander", dim=1, rho0=1.0, p0=1.0e5, gamma=1.4,
               length=1.0, height=0.12, t_end=None):
    """A Friedlander blast enters at x = 0 and loads a rigid wall at x = length (no obstacles)."""
    checks.choice("blast", blast, tuple(exact.BLASTS))
    checks.choice("negative_phase", negative_phase, NEGATIVE_PHASE)
    dim = checks.integer("dim", dim, 1, 2)
    rho0, p0 = checks.positive("rho0", rho0), checks.positive("p0", p0)
    gamma = checks.in_range("gamma", gamma, 1.0, 5.0, lo_open=True)
    length, height = checks.positive("length", length), checks.positive("height", height)
    t_end = checks.positive("t_end", (3e-3 if blast == "moderate" else 2e-3) if t_end is None else t_end)
    domain = ((0.0, length),) if dim == 1 else ((0.0, length), (0.0, height))
    dx = 1e-3
    shape = tuple(int(round((hi - lo) / dx)) for lo, hi in domain)
    times = tuple(t for t in (0.5e-3, 1.0e-3, 1.5e-3, 1.7e-3, 2.0e-3, 2.5e-3, 3.0e-3) if t < t_end) + (t_end,)
    y_mid = 0.5 * height
    return Scene(
        name="blast_wall",
        parameters=dict(blast=blast, negative_phase=negative_phase, dim=dim, rho0=rho0, p0=p0, gamma=gamma,
                        length=length, height=height, t_end=t_end),
        dim=dim, domain=domain, gamma=gamma, initial=lambda x, y, dx: (rho0, 0.0, 0.0, p0),
        boundaries={"x_lo": blast_inflow(blast, negative_phase, rho0, p0, gamma), "x_hi": "reflect",
                    "y_lo": "periodic", "y_hi": "periodic"},
        output=OutputGrid(domain=domain, shape=shape, times=times, dt_probe=1e-6),
        dx=dx, t_end=t_end, fields=("rho", "u", "v", "p", "e") if dim == 2 else ("rho", "u", "p", "e"),
        probes=(Probe("u", 0.35 * length, y_mid), Probe("d", 0.85 * length, y_mid), Probe("w", length, y_mid)),
        wall=Wall("x_hi", p0, height), measure=lambda ds: wall_load_metrics(ds, p0),
        description="Blast loading of a rigid wall; measured: peak wall pressure, arrival time, impulse.",
    )
