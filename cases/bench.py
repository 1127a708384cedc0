"""``partmesh bench``: throughput and time-to-accuracy of each method (SPEC §7).

Writes a JSON list of records ``{method, case, n_elements, metric, value,
unit, compile_seconds, ...}``. Throughput excludes JIT compile time, which
is reported beside it in every record.
"""

from __future__ import annotations

import json
import os
import platform
from pathlib import Path

from cases.registry import get
from cases.run import methods, run
from compare.metrics import field_error

#: sod L1(rho) targets for time-to-accuracy (SPEC §7)
TARGETS = (1e-2, 3e-3)
#: cell sizes tried, coarse to fine, until every target is met
SOD_LADDER = (1e-2, 5e-3, 2.5e-3, 1.25e-3, 6.25e-4, 3.125e-4)


def _machine() -> dict:
    import jax

    return {"cpu_count": os.cpu_count(), "platform": platform.platform(), "device": str(jax.devices()[0]),
            "numba_threads": os.environ.get("NUMBA_NUM_THREADS", "all")}


def fv_throughput(size: int = 512, t_end: float = 0.02) -> dict:
    """FV cell-updates per second on 2D Sedov ``size``² (float64) run to
    ``t_end`` (about 160 steps at 512²), compile time excluded."""
    scene = get("sedov", n_out=size)
    ds = run(scene, "fv", dx=scene.dx, t_end=t_end, progress=False)
    cells = ds.attrs["n_elements"]
    return {
        "method": "fv", "case": "sedov", "n_elements": cells, "metric": "cell_updates_per_s",
        "value": cells * ds.attrs["n_steps"] / ds.attrs["wall_seconds"], "unit": "cells/s",
        "compile_seconds": ds.attrs["compile_seconds"], "wall_seconds": ds.attrs["wall_seconds"],
        "n_steps": ds.attrs["n_steps"], "precision": "float64",
    }


def sph_throughput(size: int = 320, t_end: float = 2e-3) -> dict:
    """SPH particle-steps per second on 2D Sedov with ``size``² particles
    (≥ 100k at the default), compile time excluded."""
    scene = get("sedov", n_out=size)
    ds = run(scene, "sph", dx=scene.dx, t_end=t_end, progress=False)
    n = ds.attrs["n_elements"]
    return {
        "method": "sph", "case": "sedov", "n_elements": n, "metric": "particle_steps_per_s",
        "value": n * ds.attrs["n_steps"] / ds.attrs["wall_seconds"], "unit": "particles/s",
        "compile_seconds": ds.attrs["compile_seconds"], "wall_seconds": ds.attrs["wall_seconds"],
        "n_steps": ds.attrs["n_steps"], "precision": "float64",
    }


def time_to_accuracy(method: str) -> list[dict]:
    """Wall time ``method`` needs to bring L1(rho) on ``sod`` below each of
    ``TARGETS``: the run time of the coarsest resolution of ``SOD_LADDER``
    that meets it."""
    scene = get("sod")
    run(scene, method, dx=SOD_LADDER[0], progress=False)  # warm-up: first-call costs are not the method's
    records, pending = [], list(TARGETS)
    for dx in SOD_LADDER:
        ds = run(scene, method, dx=dx, progress=False)
        exact = scene.exact(ds.time.values)
        error = field_error(ds["rho"].isel(time=-1), exact["rho"].isel(time=-1))
        for target in [t for t in pending if error < t]:
            records.append({
                "method": method, "case": "sod", "n_elements": ds.attrs["n_elements"],
                "metric": f"time_to_L1_rho_below_{target:g}", "value": ds.attrs["wall_seconds"], "unit": "s",
                "compile_seconds": ds.attrs["compile_seconds"], "dx": dx, "L1_rho": error,
            })
            pending.remove(target)
        if not pending:
            break
    return records


def bench(output: str | Path = "bench.json", size: int = 512, quick: bool = False) -> list[dict]:
    """Run the benchmarks of every registered method and write ``output``."""
    records = []
    if "fv" in methods():
        records.append(fv_throughput(128 if quick else size))
        records += time_to_accuracy("fv")
    if "sph" in methods():
        records.append(sph_throughput(64 if quick else 320))
        records += time_to_accuracy("sph")
    for r in records:
        r["machine"] = _machine()
        print(f"{r['method']:5s} {r['case']:8s} {r['metric']:28s} {r['value']:.4g} {r['unit']}"
              f"  (n = {r['n_elements']}, compile {r['compile_seconds']:.2f} s)")
    Path(output).write_text(json.dumps(records, indent=2, default=float))
    print(f"benchmark written to {output}")
    return records
