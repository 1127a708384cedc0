"""Measure the record's stored runs again where the wall-load metric changed.

    python studies/blast_array/remeasure.py studies/blast_array/fv/runs studies/blast_array/sph/runs \\
        studies/blast_array/dsmc/runs

Each finished run of a blast scene (its measured quantities are those of
:func:`partmesh.cases.blast.wall_load_metrics`) is measured again from its
stored series, and its attributes are rewritten in place (the data are not
touched):

* the quantities whose value the arrival's rule changes, the first 5 %
  crossing of the transmitted wave where the last crossing before the
  maximum was read (``crossing="first"`` against ``"last"`` of
  :func:`partmesh.compare.metrics.peak`, both measured now): the arrival and
  the fitted peaks that follow it;
* ``wall_force_peak_mean``, the peak of the wall force's running mean, which
  the runs did not have.

Every other quantity keeps the value measured when the run was made (the
fitted peaks of runs made before ``a725932``, which changed where the
positive phase of a record with round-off ahead of its front starts, would
read otherwise today: those are not touched here). The run records what was
written and by which revision in ``remeasured_quantities`` and
``remeasured_revision``. Running it again writes the same values.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import netCDF4
import numpy as np

from partmesh.cases.blast import _mean_samples, wall_load_metrics
from partmesh.compare import metrics
from partmesh.compare.io import read
from partmesh.sweeps import finished

#: the quantities that follow the arrival: (measured quantity, series, fit result key)
FOLLOW = {"wall_arrival_time": ("p", "arrival"), "wall_peak_pressure_fitted": ("p", "fitted"),
          "wall_force_peak_fitted": ("force", "fitted")}
NEW = ("wall_force_peak_mean",)


def revision() -> str:
    """The commit this script runs at, with ``+changes`` where the working tree differs from it."""
    here = Path(__file__).parent
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=here, capture_output=True, text=True,
                              check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "cases", "compare"], cwd=here.parent.parent,
                               capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return head + ("+changes" if dirty else "")


def same(a: float, b: float) -> bool:
    return (math.isnan(a) and math.isnan(b)) or bool(np.isclose(a, b, rtol=1e-12, atol=0.0))


def changes(ds) -> dict:
    """The quantities of ``ds`` to rewrite: those the first crossing changes, and the new ones."""
    p0 = json.loads(ds.attrs["parameters"])["scene"]["p0"]
    now = wall_load_metrics(ds, p0)
    samples = _mean_samples(ds["wall_force"])
    series = {"p": (ds["p_probe"].sel(probe="w"), p0), "force": (ds["wall_force"], 0.0)}
    written = {}
    for quantity, (name, key) in FOLLOW.items():
        s, baseline = series[name]
        try:
            before = metrics.peak(s, baseline, crossing="last", samples=samples)[key]
        except ValueError:
            before = float("nan")
        if not same(before, now[quantity]):
            written[quantity] = now[quantity]
    written.update({q: now[q] for q in NEW})
    return written


def main(folders) -> None:
    rev = revision()
    for folder in folders:
        for path in sorted(Path(folder).glob("*.nc")):
            if not finished(path):
                continue
            ds = read(path)
            if "wall_arrival_time" not in ds.attrs:
                continue
            written = changes(ds)
            quantities = ds.attrs["measured_quantities"].split()
            quantities += [q for q in NEW if q not in quantities]
            moved = [q for q in written if q not in NEW]
            with netCDF4.Dataset(path, "a") as nc:
                for q, v in written.items():
                    nc.setncattr(q, np.float64(v))
                nc.setncattr("measured_quantities", " ".join(quantities))
                nc.setncattr("remeasured_quantities", " ".join(written))
                nc.setncattr("remeasured_revision", rev)
            print(f"{path.name}: " + (", ".join(f"{q} {ds.attrs[q]:.6g} -> {written[q]:.6g}" for q in moved)
                                      or "arrival and fitted peaks as before") + f"; {NEW[0]} {written[NEW[0]]:.6g}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__.split("\n\n")[1])
    main(sys.argv[1:])
