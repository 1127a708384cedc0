"""Speed against error of the whole moderate study, per method and spacing.

    python studies/blast_array/study_speed_error.py

One point per method and spacing whose runs of the 10 arrays are kept in
``<method>/runs``: the solver time summed over the 10, against the mean
relative difference of the wall impulse at 3 ms (and of the raw peak wall
force) from fv at 0.5 mm (``fv/wall_loads_0.5mm.csv``, the finest fv run
of every array). Writes ``methods/speed_versus_error.csv`` and
``methods/speed_versus_error_<quantity>.png``.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from partmesh.blast_study import configurations
from partmesh.compare import plots
from partmesh.compare.io import read
from partmesh.compare.report import wall_load_table
from partmesh.sweeps import finished

HERE = Path(__file__).parent
QUANTITIES = ("wall_impulse_final", "wall_force_peak_raw")


def study_points(reference: pd.DataFrame) -> pd.DataFrame:
    """One row per method and spacing with all 10 arrays kept: summed
    solver time and the mean relative error of each of ``QUANTITIES``."""
    arrays = [c for c in configurations(("moderate",)) if c.case == "blast_array"]
    labels = [c.label for c in arrays]
    fine = reference.loc[labels, list(QUANTITIES)].to_numpy()
    rows = []
    for method in ("fv", "sph", "dsmc"):
        for dx in (2e-3, 1e-3):
            paths = [HERE / method / "runs" / f"{c.run(method, dx).name}.nc" for c in arrays]
            if not all(finished(p) for p in paths):
                continue
            table = wall_load_table([read(p) for p in paths], labels)
            errors = (abs(table[list(QUANTITIES)].to_numpy() - fine) / abs(fine)).mean(axis=0)
            rows.append({"method": method, "dx": dx, "runs": len(table), "wall_seconds": table["wall_seconds"].sum(),
                         **{f"{q}_error": e for q, e in zip(QUANTITIES, errors)}})
    return pd.DataFrame(rows)


def main() -> None:
    reference = pd.read_csv(HERE / "fv" / "wall_loads_0.5mm.csv").set_index("configuration")
    points = study_points(reference)
    points.to_csv(HERE / "methods" / "speed_versus_error.csv", index=False)
    for q in QUANTITIES:
        name = q.replace("_", " ")
        print(plots.speed_versus_error(points, f"{q}_error", HERE / "methods" / f"speed_versus_error_{q}.png",
                                       f"moderate study, 10 arrays: {name} against fv at 0.5 mm",
                                       ylabel=f"mean relative error of {name}"))
    print(points.to_string(index=False))


if __name__ == "__main__":
    main()
