"""``partmesh bench``: throughput and time-to-accuracy of each method (SPEC §7).

Writes a JSON list of records ``{method, case, n_elements, metric, value,
unit, compile_seconds, ...}``. Throughput excludes JIT compile time, which
is reported beside it in every record.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

from partmesh.cases import registry
from partmesh.cases.registry import get
from partmesh.compare.metrics import field_error
from partmesh.dispatch import run

#: sod L1(rho) targets for time-to-accuracy (SPEC §7)
TARGETS = (1e-2, 3e-3)
#: settings tried, coarse to fine, until every target is met: cell sizes, and
#: for DSMC cell sizes with particles per cell (its error is scatter and cell-size dissipation)
SOD_LADDER = tuple({"dx": dx} for dx in (1e-2, 5e-3, 2.5e-3, 1.25e-3, 6.25e-4, 3.125e-4))
SOD_LADDERS = {"dsmc": tuple({"dx": 1 / cells, "ppc": ppc} for cells, ppc in ((200, 100), (400, 300), (800, 1000)))}


def _machine() -> dict:
    import jax  # (lazy: JAX loads only where a grid method or its device is asked for)

    return {"cpu_count": os.cpu_count(), "platform": platform.platform(), "device": str(jax.devices()[0]),
            "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "all")}


#: method -> (metric, unit) of its throughput record
THROUGHPUT = {"fv": ("cell_updates_per_s", "cells/s"), "sph": ("particle_steps_per_s", "particles/s"),
              "dsmc": ("particle_steps_per_s", "particles/s"), "swe": ("cell_updates_per_s", "cells/s"),
              "wcsph": ("particle_steps_per_s", "particles/s")}


def _sedov(size: int):
    scene = get("sedov", n_out=size)
    return scene, scene.dx


def _sedov_spherical(size: int):
    scene = get("sedov_spherical", n_out=size)
    return scene, scene.dx


def _sedov_3d(size: int):
    """The spherical blast in a box of as many cells as the planar one of ``size``² (64³ for 512²)."""
    scene = get("sedov_3d", n_out=round(size ** (2.0 / 3.0)))
    return scene, scene.dx


def _square_dam_break(size: int):
    scene = get("dam_break", dim=2, nx_out=size)
    return scene, scene.dx


def _prins_flume(size: int):
    scene = get("prins_mound")
    return scene, scene.depth / size


#: method -> the problem of its throughput: ``problem(size) -> (scene, dx)``
PROBLEMS = {"fv": _sedov, "sph": _sedov, "dsmc": _sedov, "swe": _square_dam_break, "wcsph": _prins_flume}


def throughput(method: str, size: int, t_end: float, problem=None, repeats: int = 1, **settings) -> list[dict]:
    """Elements advanced per second by ``method`` run to ``t_end`` with
    ``settings``, compile time excluded (output frames included), in float64
    unless ``precision`` says otherwise (``swe``). The gas methods run 2D
    Sedov with ``size``² cells or particles; :func:`bench` takes FV at 512²
    to 0.02 (about 160 steps), SPH with 448² = 200 704 particles to 3e-3
    (about 20 steps), DSMC on 258² cells of 30 particles (2.0 million) to
    8e-3 (about 45 steps: move, sort, redraw and sampling). ``swe`` runs the
    dam break across a square basin on ``size``² cells (1024² to 0.05 s,
    130 steps; :func:`bench` runs it in float64 and in float32), ``wcsph``
    the Prins flume (30 m × 0.7 m) with ``size`` particles over the depth
    (50: 107 000 particles, to 0.01 s, about 45 steps). SPH adds the interactions per second of its force pass (the
    ordered pairs i–j with r_ij < max(H_i, H_j) whose terms it summed, over
    the seconds spent in that pass; each pair is evaluated once for both
    particles), as does WCSPH (pairs within its one support H). ``problem``
    replaces the method's problem (:data:`PROBLEMS`): :func:`bench` runs
    ``fv`` on the spherical Sedov blast in r–z too, on as many cells as the
    planar one, for the rate of the axisymmetric scheme, and in a 3D box
    (to 0.1, about 120 steps at 64³) for the rate of the 3D step. A refined ``fv``
    run (``levels`` > 1) counts the cell updates its levels made (its
    ``cell_updates``), so its rate compares with the uniform grid's per
    cell updated. With ``repeats`` > 1 the run is made that many times and the
    fastest kept: the first run of a size in a process also pays for touching
    its arrays' memory for the first time (1.5 s of 8 at 2048², measured), a
    cost of the first run like its compile, not of its steps."""
    scene, dx = (problem or PROBLEMS[method])(size)
    runs = [run(scene, method, dx=dx, t_end=t_end, progress=False, **settings) for _ in range(repeats)]
    ds = min(runs, key=lambda d: d.attrs["wall_seconds"])
    n = ds.attrs["n_elements"]
    metric, unit = THROUGHPUT[method]
    common = {"method": method, "case": scene.name, "n_elements": n, "repeats": repeats,
              "compile_seconds": runs[0].attrs["compile_seconds"],
              "wall_seconds": ds.attrs["wall_seconds"], "n_steps": ds.attrs["n_steps"],
              "precision": settings.get("precision", "float64")}
    if "cell_updates" in ds.attrs:  # a refined run: the cells its levels updated, per second
        common["levels"] = ds.attrs["levels"]
        updates = ds.attrs["cell_updates"]
    else:
        updates = n * ds.attrs["n_steps"]
    records = [{**common, "metric": metric, "value": updates / ds.attrs["wall_seconds"], "unit": unit}]
    if method in ("sph", "wcsph"):
        passes = [k for k in ("seconds_search", "seconds_density", "seconds_forces") if k in ds.attrs]
        records.append({**common, "metric": "force_interactions_per_s", "unit": "interactions/s",
                        "value": ds.attrs["force_interactions"] / ds.attrs["seconds_forces"],
                        **{k: ds.attrs[k] for k in passes}})
    return records


def time_to_accuracy(method: str) -> list[dict]:
    """Wall time ``method`` needs to bring L1(rho) on ``sod`` below each of
    ``TARGETS``: the run time of the cheapest settings of its ladder
    (``SOD_LADDERS``, else ``SOD_LADDER``) that meet it."""
    scene = get("sod")
    ladder = SOD_LADDERS.get(method, SOD_LADDER)
    run(scene, method, **ladder[0], progress=False)  # warm-up: first-call costs are not the method's
    records, pending = [], list(TARGETS)
    for settings in ladder:
        ds = run(scene, method, **settings, progress=False)
        exact = scene.exact(ds.time.values)
        error = field_error(ds["rho"].isel(time=-1), exact["rho"].isel(time=-1))
        for target in [t for t in pending if error < t]:
            records.append({
                "method": method, "case": "sod", "n_elements": ds.attrs["n_elements"],
                "metric": f"time_to_L1_rho_below_{target:g}", "value": ds.attrs["wall_seconds"], "unit": "s",
                "compile_seconds": ds.attrs["compile_seconds"], **settings, "L1_rho": error,
            })
            pending.remove(target)
        if not pending:
            break
    return records


#: sod cell sizes of a cold-process run (:func:`cold_process`): the first, then one not run before (240 cells:
#: hybrid's coarse cells, four of these, must tile the tube too)
COLD_DX = (5e-3, 1.0 / 240)


def cold_process(method: str) -> dict:
    """The seconds ``pm.run("sod", method)`` takes end to end, import
    included, in a fresh Python process after one earlier run (compiled
    code cached on disk, nothing in memory), at a cell size not run before
    (:data:`COLD_DX`): what a user waits for a first run in a new session."""
    code = (f"import time; t0 = time.perf_counter(); import partmesh as pm; "
            f"ds = pm.run('sod', {method!r}, dx={COLD_DX[1]!r}, progress=False); "
            "print(ds.attrs['n_elements'], time.perf_counter() - t0)")
    run(get("sod"), method, dx=COLD_DX[0], progress=False)  # (the earlier run: its compiled code on disk)
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    n, seconds = done.stdout.split()[-2:]
    return {"method": method, "case": "sod", "n_elements": int(n), "metric": "cold_process_seconds",
            "value": float(seconds), "unit": "s", "compile_seconds": float("nan"),
            "process_seconds": time.perf_counter() - t0}


#: (cells across, t_end) of the small 2D Sedov grids of ``fv`` (about 60 and 110 steps)
SMALL_FV_GRIDS = ((64, 0.15), (128, 0.08))
#: (cells across, t_end) of the large 2D Sedov grids of ``fv`` (about 60 steps each): the rate against size
LARGE_FV_GRIDS = ((1024, 0.004), (2048, 0.001))
#: the end of the 3D Sedov run of ``fv`` (its rate against the 2D step's on as many cells)
SEDOV_3D_END = 0.1
#: (finest cells across, levels, t_end) of the refined 2D Sedov run of ``fv``: the rate per cell updated
REFINED_FV = (512, 3, 0.1)


def bench(output: str | Path = "bench.json", size: int = 512, quick: bool = False) -> list[dict]:
    """Run the benchmarks of every registered method and write ``output``."""
    records = []
    sizes = {"fv": (128 if quick else size, 0.02), "sph": (64 if quick else 448, 3e-3),
             "dsmc": (64 if quick else 258, 8e-3), "swe": (128 if quick else 1024, 0.05),
             "wcsph": (12 if quick else 50, 0.01)}
    registered = registry.methods()
    for method in (m for m in THROUGHPUT if m in registered):
        records += throughput(method, *sizes[method], repeats=2 if method == "fv" else 1)
        if method == "swe":
            records += throughput(method, *sizes[method], precision="float32")
        if method == "fv":
            records += throughput(method, *sizes[method], problem=_sedov_spherical)
            records += throughput(method, sizes[method][0], SEDOV_3D_END, problem=_sedov_3d)
        if method == "fv" and not quick:
            # small grids, long enough to be timed: the rate a step loop keeps when a grid is small
            for n, t_end in SMALL_FV_GRIDS + LARGE_FV_GRIDS:
                records += throughput(method, n, t_end, repeats=2)
            n, levels, t_end = REFINED_FV
            records += throughput(method, n, t_end, levels=levels, repeats=2)
    for method in (m for m in registered if registry.method(m).medium == "gas"):  # (sod is a gas scene)
        records += time_to_accuracy(method)
        records.append(cold_process(method))
    for r in records:
        r["machine"] = _machine()
        print(f"{r['method']:5s} {r['case']:15s} {r['metric']:28s} {r['value']:.4g} {r['unit']}"
              f"{'' if r.get('precision', 'float64') == 'float64' else ' (' + r['precision'] + ')'}"
              f"  (n = {r['n_elements']}, compile {r['compile_seconds']:.2f} s)")
    Path(output).write_text(json.dumps(records, indent=2, default=float))
    print(f"benchmark written to {output}")
    return records
