"""Reports over result files: the scene side of ``partmesh compare`` (it
rebuilds the scene from a result's parameters to get its exact solution)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from cases.errors import InputError
from cases.registry import get
from compare.io import read
from compare.report import report, scene_of, table


def exact_reference(ds):
    """The exact solution of the scene ``ds`` was run on, at its output
    times, with the quantities the scene measures where its exact solution
    holds what they are measured from (the gauge records of linear wave
    theory, for one)."""
    params = dict(scene_of(ds))
    case = params.pop("case")
    times = ds.time.values[ds.time.values > 0.0]  # (a point blast's similarity solution has no t = 0)
    scene = get(case, **params)
    reference = scene.exact(times) if times.size else None
    if reference is None:
        raise InputError(f"scene {case} has no exact solution; pass a reference result with --reference FILE.")
    if scene.measure is not None and all(name in reference for name in ("probe", scene.probe_variable)):
        reference.attrs.update(scene.measure(reference))  # (gauge crests of linear theory, for one)
    return reference


def compare_files(paths, reference: str = "exact", output: str | Path = "report") -> pd.DataFrame:
    """Error table and figures of the result files ``paths`` against
    ``reference`` ('exact', 'none', or a result file), written to ``output``
    (:func:`compare.report.report`)."""
    runs = [read(p) for p in paths]
    names = [Path(p).stem for p in paths]
    if reference == "exact":
        ref = exact_reference(runs[0])
    elif reference == "none":
        ref = None
    else:
        ref = read(reference)
        table([ref, runs[0]], None, [Path(reference).stem, names[0]])  # same scene and grid, or refuse
    return report(runs, ref, names, output, versus="exact" if reference == "exact" else Path(reference).stem)
