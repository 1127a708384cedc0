"""``partmesh demo``: a small end-to-end method study on built-in defaults.

Runs ``sod`` and ``blast_wall`` (1D) with every registered gas method at two
resolutions, writes each result as netCDF, and a report per scene: the
error table (against the exact solution for ``sod``, against the finest run
for ``blast_wall``) and figures. A run shorter than two seconds is timed as
the best of three (:func:`partmesh.dispatch.best_timed_run`); the load
average at the start is printed and written on the speed-against-error
figures. The methods' kernels are compiled first, side by side in
processes of their own (:func:`partmesh.warmup.warm`), so the timed runs
hold no compile and a first demo waits for the longest compile, not the
sum.
"""

from __future__ import annotations

import os
from pathlib import Path

from partmesh.cases.errors import Unsupported
from partmesh.cases.registry import get, methods
from partmesh.compare.io import write
from partmesh.compare.report import report
from partmesh.dispatch import REPEATS, SHORT_RUN, best_timed_run
from partmesh.warmup import warm

#: scene -> cell sizes (coarse, fine); blast_wall at 4 and 2 mm, where its sph runs take about 6 and 17 s (1 mm: 40 s)
RESOLUTIONS = {"sod": (5e-3, 2.5e-3), "blast_wall": (4e-3, 2e-3)}
GAS_METHODS = ("fv", "sph", "dsmc")
#: the methods by the time their first compile takes, longest first (the order :func:`warm` starts them)
LONGEST_COMPILE_FIRST = ("sph", "dsmc", "fv")


def plan(methods=GAS_METHODS) -> dict[str, list[tuple[str, dict]]]:
    """The demo's runs of each of ``methods``, longest compile first, for :func:`partmesh.warmup.warm`."""
    runs = [(case, {"dx": dx}) for case, resolutions in RESOLUTIONS.items() for dx in resolutions]
    return {m: runs for m in sorted(methods, key=LONGEST_COMPILE_FIRST.index)}


def demo(folder: Path = Path("partmesh-demo"), progress: bool = True) -> Path:
    """Run the demo study into ``folder``; return it."""
    folder = Path(folder)
    available = [m for m in GAS_METHODS if m in methods()]
    load = os.getloadavg()[0]
    timing = f"solver time, best of {REPEATS} below {SHORT_RUN:g} s; load average {load:.2f} at the start"
    print(timing)
    warm(plan(available), progress=progress)
    for case, resolutions in RESOLUTIONS.items():
        scene = get(case)
        runs, names = [], []
        for method in available:
            for dx in resolutions:
                name = f"{case}_{method}_dx{dx:g}"
                try:
                    ds = best_timed_run(scene, method, dx=dx, progress=progress)
                except Unsupported as reason:
                    print(f"  {method} skipped: {reason}")
                    break
                write(ds, folder / "runs" / f"{name}.nc")
                runs.append(ds)
                names.append(f"{method} dx={dx:g}")
                print(f"  {name}: {ds.attrs['n_steps']} steps in {ds.attrs['wall_seconds']:.3g} s "
                      f"({ds.attrs['timing']}; +{ds.attrs['compile_seconds']:.2f} s compile)")
        reference = scene.exact(runs[0].time.values)
        versus = "exact"
        if reference is None:
            finest = min(range(len(runs)), key=lambda i: runs[i].attrs["dx"])
            reference, versus = runs[finest], f"the finest run ({names[finest]})"
        df = report(runs, reference, names, folder / case, versus=versus, timing=timing)
        cols = [c for c in ("run", "method", "dx", "wall_seconds", "rho_L1", "p_L1", "wall_peak_pressure_fitted",
                            "wall_impulse_final") if c in df]
        print(df[cols].to_string(index=False))
    print(f"demo report written to {folder.resolve()}")
    return folder
