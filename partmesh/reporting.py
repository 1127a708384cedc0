"""Reports over results: :func:`report`, the scene side of ``partmesh
compare`` (it rebuilds the scene from a result's parameters to get its
exact solution)."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import xarray as xr

from partmesh.cases.errors import InputError
from partmesh.cases.registry import get
from partmesh.compare.io import read
from partmesh.compare.report import IncompatibleResults, scene_of, table
from partmesh.compare.report import report as compare_report

__all__ = ["IncompatibleResults", "exact_reference", "report"]


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


def report(results, reference="exact", output: str | Path = "report", names=None) -> pd.DataFrame:
    """The error table and figures of ``results`` (result files or
    Datasets of one scene) against ``reference``: ``"exact"`` (the scene's
    exact solution), ``None`` (no reference), or a result (file or
    Dataset) of the same scene and grid; written to ``output``
    (:func:`partmesh.compare.report.report`) and returned. ``names`` label
    the runs (default: the file stems, or method and dx). Results of
    different scenes or grids raise :class:`~partmesh.compare.report.IncompatibleResults`."""
    runs = [r if isinstance(r, xr.Dataset) else read(r) for r in results]
    if names is None:
        names = [_name(r, ds) for r, ds in zip(results, runs)]
    if isinstance(reference, str) and reference == "exact":
        ref, versus = exact_reference(runs[0]), "exact"
    elif reference is None or (isinstance(reference, str) and reference == "none"):
        ref, versus = None, "the reference"
    else:
        ref = reference if isinstance(reference, xr.Dataset) else read(reference)
        versus = _name(reference, ref)
        table([ref, runs[0]], None, [versus, names[0]])  # same scene and grid, or refuse
    return compare_report(runs, ref, list(names), output, versus=versus)


def _name(given, ds: xr.Dataset) -> str:
    """A run's label: its file's stem, or its method and spacing."""
    return f"{ds.attrs['method']} dx={ds.attrs['dx']:g}" if isinstance(given, xr.Dataset) else Path(given).stem
