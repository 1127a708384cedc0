"""Sod's shock tube with ``fv`` side by side with Clawpack's 1D Euler solver:
the scene ``sod`` at its defaults (x in [0, 1], diaphragm at x = 0.5, left
rho, u, p = 1, 0, 1, right 0.125, 0, 0.1, gamma = 1.4, outflow
(extrapolating) boundaries, to t = 0.2 s) on N = 100, 200, 400, 800 cells:
solver seconds (best of 5; compile and set-up time excluded), steps, and
L1(rho) at t = 0.2 against the exact Riemann solution
(:func:`partmesh.compare.exact.riemann`).

Clawpack (``pip install clawpack``, which builds its Fortran with gfortran):
PyClaw's classic Fortran solver (``ClawSolver1D``, second order, Roe solver
with Harten-Hyman entropy fix ``riemann.euler_with_efix_1D``, idle here:
Sod's rarefaction is not transonic; MC limiter, cfl_desired 0.9, cfl_max
1.0), output disabled; only ``claw.run()`` is timed. ``fv`` runs with its
defaults (unsplit MUSCL-Hancock, MC limiter on primitive variables, HLLC,
Courant number 0.8), once untimed at each size first so that JIT
compilation and first-call costs stay out; its time is the result's
``wall_seconds`` (compile time, ``compile_seconds``, is reported apart) and
includes stopping at the scene's extra output time t = 0.1 (one shortened
step, a frame and probe sampling), which Clawpack does not have.

L1(rho) is :func:`partmesh.compare.metrics.field_error`'s, the cell-width-weighted
mean sum_i |rho_i - rho_exact(x_i)| dx / sum_i dx (on a uniform grid the
plain mean over cells), the exact solution taken at the cell centres. Both
codes are measured on their own N cells (``fv`` runs ``sod`` with
``nx_out = N`` so its output grid is its solver grid). ``fv L1 @400`` is
the error as ``partmesh bench`` (``partmesh.bench.time_to_accuracy``) measures
it: the default scene's 400-cell output grid, onto which ``fv`` moves its
N-cell result (linear interpolation for N = 100, 200; the 2-cell average
for N = 800). The JSON records also hold both codes' L1(rho) against the
exact solution's cell averages rather than its centre values (lower: 9.3e-4
instead of 1.07e-3 for Clawpack at 400 cells). Run it on one thread, as
Clawpack runs by default::

    OMP_NUM_THREADS=1 python benchmarks/clawpack_sod.py [--json FILE] [--repeat 5] [N ...]

The times are milliseconds, and on a loaded machine single runs scatter
by up to tens of times (``fv`` more than Clawpack): only the best of the
repeats means much.
"""

import argparse
import json
import time

import numpy as np
import xarray as xr
from clawpack import pyclaw, riemann
from clawpack.riemann.euler_with_efix_1D_constants import density, energy, momentum, num_eqn

import partmesh
from partmesh.compare import exact
from partmesh.compare.metrics import field_error

SIZES = (100, 200, 400, 800)
LEFT, RIGHT, X0, GAMMA, T_END = (1.0, 0.0, 1.0), (0.125, 0.0, 0.1), 0.5, 1.4, 0.2


def scene(n: int | None = None):
    """The ``sod`` scene (its defaults are the problem above), with an
    ``n``-cell output grid if ``n`` is given."""
    s = partmesh.scene("sod") if n is None else partmesh.scene("sod", nx_out=n)
    p = s.parameters
    assert ((p["left_rho"], p["left_u"], p["left_p"]), (p["right_rho"], p["right_u"], p["right_p"]),
            p["x0"], p["gamma"], s.t_end) == (LEFT, RIGHT, X0, GAMMA, T_END), "the sod scene's defaults changed"
    return s


def l1_rho(rho: xr.DataArray, s) -> float:
    """L1(rho) at t_end of ``rho`` on the output grid of scene ``s``."""
    return field_error(rho, s.exact([T_END])["rho"].isel(time=-1))


def l1_rho_cell_averages(rho: xr.DataArray, subcells: int = 64) -> float:
    """L1(rho) at t_end against the exact solution's cell averages (the mean
    of ``subcells`` point values across each cell) instead of its values at
    the cell centres: the two differ only in the cells the contact and the
    shock cross (about 1.4e-4 at 400 cells), and this one gives lower errors."""
    x = rho.x.values
    dx = x[1] - x[0]
    fine = (x[:, None] - 0.5 * dx + (np.arange(subcells) + 0.5) * dx / subcells).ravel()
    point = exact.riemann(LEFT, RIGHT, fine, [T_END], x0=X0, gamma=GAMMA)["rho"].values[-1]
    average = point.reshape(x.size, subcells).mean(1)
    return float(np.mean(np.abs(rho.values - average)))


def clawpack_controller(n: int) -> pyclaw.Controller:
    """PyClaw's classic solver on Sod with ``n`` cells, set up, not run."""
    solver = pyclaw.ClawSolver1D(riemann.euler_with_efix_1D)
    solver.limiters, solver.order, solver.cfl_desired, solver.cfl_max = pyclaw.limiters.tvd.MC, 2, 0.9, 1.0
    solver.kernel_language = "Fortran"
    solver.bc_lower[0] = solver.bc_upper[0] = pyclaw.BC.extrap
    domain = pyclaw.Domain([pyclaw.Dimension(0.0, 1.0, n, name="x")])
    state = pyclaw.State(domain, num_eqn)
    state.problem_data["gamma"] = GAMMA  # the Fortran's common block /cparam/ gamma
    state.problem_data["gamma1"] = GAMMA - 1.0
    x = state.grid.x.centers
    left = x < X0
    rho = np.where(left, LEFT[0], RIGHT[0])
    u = np.where(left, LEFT[1], RIGHT[1])
    p = np.where(left, LEFT[2], RIGHT[2])
    state.q[density] = rho
    state.q[momentum] = rho * u
    state.q[energy] = p / (GAMMA - 1.0) + 0.5 * rho * u**2
    claw = pyclaw.Controller()
    claw.tfinal, claw.solution, claw.solver = T_END, pyclaw.Solution(state, domain), solver
    claw.num_output_times, claw.output_format, claw.keep_copy, claw.verbosity = 1, None, True, 0
    solver.dt_initial = 0.5 * (1.0 / n) / np.sqrt(GAMMA * LEFT[2] / LEFT[0])  # half the CFL limit at t = 0
    solver.setup(claw.solution)
    return claw


def clawpack_run(n: int, repeat: int) -> dict:
    """Best-of-``repeat`` time of ``claw.run()``, its steps and L1(rho)."""
    seconds = []
    for _ in range(repeat):
        claw = clawpack_controller(n)
        t0 = time.perf_counter()
        claw.run()
        seconds.append(time.perf_counter() - t0)
    frame = claw.frames[-1]
    assert abs(frame.t - T_END) < 1e-12, frame.t
    x = frame.state.grid.x.centers
    rho = xr.DataArray(np.array(frame.q[density]), coords={"x": x}, dims="x")
    return {"seconds": min(seconds), "all_seconds": seconds, "steps": int(claw.solver.status["numsteps"]),
            "L1_rho": l1_rho(rho, scene(n)), "L1_rho_cell_averages": l1_rho_cell_averages(rho)}


def fv_run(n: int, repeat: int) -> dict:
    """Best-of-``repeat`` ``wall_seconds`` of ``fv`` on ``n`` cells, its
    steps, compile seconds and L1(rho) on its own grid and on the default
    400-cell output grid (as ``partmesh bench`` measures it)."""
    native = scene(n)
    partmesh.run(native, "fv", dx=1.0 / n, progress=False)  # warm-up at this size: first-call costs are not the method's
    runs = [partmesh.run(native, "fv", dx=1.0 / n, progress=False) for _ in range(repeat)]
    ds = min(runs, key=lambda r: r.attrs["wall_seconds"])
    assert ds.sizes["x"] == n and np.isclose(ds.time.values[-1], T_END)
    bench_scene = scene()
    bench = partmesh.run(bench_scene, "fv", dx=1.0 / n, progress=False)  # (untimed: only its error is used)
    return {"seconds": ds.attrs["wall_seconds"], "all_seconds": [r.attrs["wall_seconds"] for r in runs],
            "steps": int(ds.attrs["n_steps"]),
            "compile_seconds": min(r.attrs["compile_seconds"] for r in runs),
            "L1_rho": l1_rho(ds["rho"].isel(time=-1), native),
            "L1_rho_cell_averages": l1_rho_cell_averages(ds["rho"].isel(time=-1)),
            "L1_rho_400": l1_rho(bench["rho"].isel(time=-1), bench_scene),
            "regrid_400": bench.attrs.get("regrid", "?")}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("sizes", nargs="*", type=int, default=SIZES, help="cell counts (default 100 200 400 800)")
    parser.add_argument("--repeat", type=int, default=5, help="timed runs per code and size, best kept (default 5)")
    parser.add_argument("--json", metavar="FILE", help="write the records to FILE as JSON")
    args = parser.parse_args()

    print(f"Sod shock tube to t = {T_END}: solver seconds (best of {args.repeat}), steps, L1(rho) vs exact")
    print("  Clawpack: classic, Roe + entropy fix, MC, CFL 0.9; fv: MUSCL-Hancock, HLLC, MC, CFL 0.8")
    print("  L1 on each code's own N cells; 'fv L1 @400' on the scene's default 400-cell output grid "
          "(as partmesh bench)")
    header = (f"{'N':>5} {'claw s':>9} {'claw st':>7} {'claw L1':>9} {'fv s':>9} {'fv st':>6} {'fv L1':>9} "
              f"{'fv/claw':>8} {'fv L1 @400':>10} {'fv compile s':>12}")
    print(header)
    records = []
    for n in args.sizes:
        c, f = clawpack_run(n, args.repeat), fv_run(n, args.repeat)
        record = {"N": n, "clawpack_seconds": c["seconds"], "clawpack_steps": c["steps"],
                  "clawpack_L1_rho": c["L1_rho"],
                  "fv_seconds": f["seconds"], "fv_steps": f["steps"], "fv_L1_rho": f["L1_rho"],
                  "ratio_fv_over_clawpack": f["seconds"] / c["seconds"], "fv_L1_rho_output_grid_400": f["L1_rho_400"],
                  "fv_regrid_to_400": f["regrid_400"], "fv_compile_seconds": f["compile_seconds"],
                  "clawpack_L1_rho_vs_exact_cell_averages": c["L1_rho_cell_averages"],
                  "fv_L1_rho_vs_exact_cell_averages": f["L1_rho_cell_averages"], "repeat": args.repeat,
                  "clawpack_seconds_all": c["all_seconds"], "fv_seconds_all": f["all_seconds"]}
        records.append(record)
        print(f"{n:5d} {c['seconds']:9.4f} {c['steps']:7d} {c['L1_rho']:9.3e} {f['seconds']:9.4f} {f['steps']:6d} "
              f"{f['L1_rho']:9.3e} {record['ratio_fv_over_clawpack']:8.2f} {f['L1_rho_400']:10.3e} "
              f"{f['compile_seconds']:12.2f}", flush=True)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(records, fh, indent=2)
        print(f"records written to {args.json}")


if __name__ == "__main__":
    main()
