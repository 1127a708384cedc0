"""Sweeps: every combination of scene parameters, solver settings, methods
and resolutions of one scene as independent runs on Dask, one netCDF file
per run (SPEC §6, §8).

A run's file is named from its parameters (``sod_fv_dx0.005_x0-0.4.nc``),
written atomically by the worker that ran it, and a sweep skips every run
whose file already holds a complete result: a sweep that was stopped
half-way is finished by running it again. A run that fails writes its
partial result (``status = "failed"``, which the next sweep runs again)
and is reported at the end; the others go on. Every run of a method that
checkpoints saves its state to ``<name>.nc.checkpoint`` every
``checkpoint_every`` seconds of wall time (600 by default) and resumes from
it when the sweep runs again. Ctrl-C or SIGTERM stops a sweep cleanly: each
run under way ends its step and saves its state and its partial result, and
no other run begins (:mod:`partmesh.cases.checkpoint`). :func:`open_sweep` opens the
finished runs together with ``xarray.open_mfdataset``, along a dimension
``run`` that carries each run's method, ``dx``, scene parameters and
solver settings as coordinates.
"""

from __future__ import annotations

import itertools
import re
import time
from dataclasses import dataclass, fields
from pathlib import Path

import xarray as xr
from tqdm.auto import tqdm

from partmesh.cases import registry
from partmesh.cases.checkpoint import Interrupted, clear_stop_request, request_stop, signals_raised, stop_requested
from partmesh.cases.errors import InputError, SolverFailed
from partmesh.cases.registry import defaults, get
from partmesh.cluster import dask_client, local_workers, threads_per_run
from partmesh.compare.io import opened, write
from partmesh.compare.schema import SchemaError, parameters
from partmesh.dispatch import run as run_scene


@dataclass(frozen=True)
class SweepRun:
    """One run of a sweep: ``values`` are its swept ``(key, value)`` pairs
    (scene parameters or solver settings), in the order they were given."""
    case: str
    method: str
    dx: float | None
    values: tuple = ()

    @property
    def name(self) -> str:
        """The file stem: case, method, dx and the swept values."""
        parts = [self.case, self.method] + ([f"dx{self.dx:g}"] if self.dx is not None else [])
        parts += [f"{key}-{value}" for key, value in self.values]
        return re.sub(r"[^A-Za-z0-9.+=_-]", "-", "_".join(str(p) for p in parts))


def plan(case: str, methods, dx=(None,), values: dict | None = None) -> list[SweepRun]:
    """The runs of a sweep: the cartesian product of ``methods``, ``dx``
    values and every list in ``values`` (key -> values), in that order. A
    value sweeps a method's runs only where the key is a scene parameter or
    a setting of that method (``ppc`` sweeps dsmc, not fv, which then runs
    once). Refuses an unknown method, a key that is neither a parameter of
    the scene nor a setting of any of the methods, or an empty list, with
    one sentence."""
    methods, dx = list(methods), list(dx)
    unknown = [m for m in methods if m not in registry.methods()]
    if unknown:
        raise InputError(f"unknown method {unknown[0]!r}; available methods: {', '.join(sorted(registry.methods()))}.")
    values = dict(values or {})
    for key, options in {"methods": methods, "dx": dx, **values}.items():
        if not list(options):
            raise InputError(f"sweep {key} needs at least one value.")
    scene_keys = set(defaults(case))
    takes = {method: scene_keys | solver_settings(method) for method in methods}
    for key in values:
        if not any(key in keys for keys in takes.values()):
            raise InputError(f"{key!r} is neither a parameter of scene {case} nor a setting of "
                             f"{', '.join(methods)}.")
    runs = []
    for method, step in itertools.product(methods, dx):
        keys = [k for k in values if k in takes[method]]
        runs += [SweepRun(case, method, step, tuple(zip(keys, combo)))
                 for combo in itertools.product(*(values[k] for k in keys))]
    return runs


def solver_settings(method: str) -> set:
    """The names of ``method``'s settings."""
    return {f.name for f in fields(registry.method(method).settings)}


def finished(path: str | Path) -> bool:
    """Whether ``path`` holds a complete partmesh result (a readable file
    whose ``status`` is ``"ok"``; its data are not read)."""
    try:
        with opened(path) as ds:
            return ds.attrs.get("status") == "ok"
    except (FileNotFoundError, SchemaError):
        return False


def sweep(case: str, methods, dx=(None,), values: dict | None = None, output: str | Path = "runs",
          settings: dict | None = None, scheduler: str | None = None, workers: int | None = None,
          progress: bool = True) -> list[dict]:
    """Run every run of :func:`plan` that ``output`` does not hold finished
    yet (:func:`execute`). ``settings`` go to every run of a method that
    takes them (``t_end``, ``cfl``; ``seed`` to dsmc, ...). Returns one record per run: ``name``, ``path``,
    ``status`` (``"ran"``, ``"done before"`` or ``"failed"``), ``seconds``
    and ``message``."""
    return execute(plan(case, methods, dx, values), output, settings, scheduler, workers, progress,
                   f"sweep {case}")


def execute(runs: list[SweepRun], output: str | Path = "runs", settings: dict | None = None,
            scheduler: str | None = None, workers: int | None = None, progress: bool = True,
            description: str = "runs") -> list[dict]:
    """Run every one of ``runs`` that ``output`` does not hold finished yet,
    on the Dask scheduler at ``scheduler`` or on a LocalCluster of
    ``workers`` single-threaded processes (default: one per core), each
    writing ``output/<name>.nc``; ``settings`` go to every run of a method
    that takes them. A bad scene parameter or setting is refused before
    anything runs. Returns the records of :func:`sweep`, in the order of
    ``runs``; stopped by a signal, raises
    :class:`~partmesh.cases.errors.SolverFailed` (:func:`_collected`)."""
    settings = dict(settings or {})
    methods = sorted({run.method for run in runs})
    takes = {m: solver_settings(m) for m in methods}
    for key in settings:
        if not any(key in keys for keys in takes.values()):
            raise InputError(f"{key!r} is not a setting of {', '.join(methods)}.")
    for key in ("checkpoint", "resume"):
        if key in settings:
            raise InputError(f"{key} is not a setting of a sweep: each run saves its state to <its file>.checkpoint "
                             f"every checkpoint_every seconds and resumes from it when the sweep runs again.")
    scene_keys = {run.case: set(defaults(run.case)) for run in runs}
    for run in runs:  # a bad scene parameter is refused before anything runs
        _scene(run, scene_keys[run.case])
    output = Path(output)
    output.mkdir(parents=True, exist_ok=True)
    records, todo = [], []
    for run in runs:
        path = output / f"{run.name}.nc"
        if finished(path):
            records.append({"name": run.name, "path": str(path), "status": "done before", "seconds": 0.0,
                            "message": ""})
        else:
            todo.append((run, path))
    if todo:
        n_workers = local_workers(len(todo), workers)
        threads = None if scheduler else threads_per_run(n_workers)
        with dask_client(scheduler, n_workers) as client, \
                tqdm(total=len(todo), disable=None if progress else True, desc=description, unit="run") as bar:
            futures = [client.submit(_run_and_write, run, str(path), sorted(scene_keys[run.case]),
                                     {k: v for k, v in settings.items() if k in takes[run.method]},
                                     threads, "checkpoint" in takes[run.method], pure=False) for run, path in todo]
            records += _collected(client, futures, bar, description)
    order = {run.name: k for k, run in enumerate(runs)}
    return sorted(records, key=lambda r: order[r["name"]])


def _collected(client, futures, bar, description: str) -> list[dict]:
    """The records of ``futures`` as they finish. A SIGINT or SIGTERM
    meanwhile asks every worker's runs to stop: each run under way ends its
    step and writes its state and partial result, a run not begun does not
    begin; then (or when a signal to a worker alone kept a run from
    beginning) :class:`~partmesh.cases.errors.SolverFailed` says how many of each."""
    from distributed import as_completed  # (lazy: Dask, ~1 s to import, only for runs on a cluster)

    records, stop = {}, None
    try:
        with signals_raised():
            for future in as_completed(futures):
                record = future.result()
                records[record["name"]] = record
                bar.update(1)
    except Interrupted as interrupted:
        stop = interrupted.signal
        bar.write(f"{description}: stopping on {stop}; the runs under way end their step and save "
                  f"(a second {stop} ends at once)")
        client.run(request_stop, stop)
        for future in futures:
            record = future.result()
            records.setdefault(record["name"], record)
    counts = {s: sum(r["status"] == s for r in records.values()) for s in ("ran", "failed", "not begun")}
    if stop is None and not counts["not begun"]:
        return list(records.values())
    client.run(clear_stop_request)
    raise SolverFailed(f"{description} stopped by {stop or 'a signal to its workers'}: {counts['ran']} runs "
                       f"finished, {counts['failed']} ended early with their partial result (and state, to resume "
                       f"from) written, {counts['not begun']} not begun; the same command again goes on from there.")


def _scene(run: SweepRun, scene_keys):
    return get(run.case, **{k: v for k, v in run.values if k in scene_keys})


def _run_and_write(run: SweepRun, path: str, scene_keys, settings: dict, threads: int | None,
                   checkpointed: bool) -> dict:
    """One run on a worker: its result (or its partial result, when it
    fails) written atomically to ``path``; ``checkpointed``: its state
    saved to ``path.checkpoint`` (:mod:`partmesh.cases.checkpoint`), resumed from
    there when that file exists, and removed once the run is complete. Not
    begun (status ``"not begun"``) when its process was asked to stop."""
    record, stop = {"name": run.name, "path": path}, stop_requested()
    if stop is not None:
        return {**record, "status": "not begun", "seconds": 0.0, "message": f"not begun: the sweep was stopped by {stop}."}
    if threads:
        import numba  # (lazy: numba loads only in a worker that runs particles)

        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    given = {**settings, **{k: v for k, v in run.values if k not in scene_keys}, "progress": False}
    if run.dx is not None:
        given["dx"] = run.dx
    checkpoint = Path(path + ".checkpoint")
    if checkpointed:
        given.update(checkpoint=checkpoint, resume=checkpoint.is_file())
    t0 = time.perf_counter()
    try:
        ds = run_scene(_scene(run, scene_keys), run.method, **given)
    except SolverFailed as failure:
        if failure.partial is not None:
            write(failure.partial, path)
        return {**record, "status": "failed", "seconds": time.perf_counter() - t0, "message": str(failure)}
    except InputError as err:
        return {**record, "status": "failed", "seconds": time.perf_counter() - t0, "message": str(err)}
    write(ds, path)
    checkpoint.unlink(missing_ok=True)  # the run is complete
    return {**record, "status": "ran", "seconds": time.perf_counter() - t0, "message": ""}


def open_sweep(folder: str | Path, **kwargs):
    """The finished runs in ``folder`` as one Dataset (``open_mfdataset``,
    lazily), stacked along ``run``, with coordinates on it: ``method``,
    ``dx`` and every scalar scene parameter or solver setting that differs
    between the runs (NaN or "" for a run whose method has no such setting).
    Runs of one scene share its output grid; ``kwargs`` go to
    ``open_mfdataset``."""
    paths = sorted(str(p.resolve()) for p in Path(folder).glob("*.nc") if finished(p))
    if not paths:
        raise FileNotFoundError(f"no finished partmesh results in {str(folder)!r}.")
    labels = _run_labels(paths)
    return xr.open_mfdataset(paths, combine="nested", concat_dim="run", combine_attrs="drop_conflicts",
                             data_vars="all", coords="minimal", compat="override",
                             preprocess=lambda ds: ds.expand_dims("run").assign_coords(
                                 {k: ("run", [v[ds.encoding["source"]]]) for k, v in labels.items()}),
                             **kwargs)


def _run_labels(paths) -> dict:
    """key -> {path: value} for ``method``, ``dx`` and the scalar scene
    parameters and solver settings (a setting wins over a scene parameter
    of the same name, e.g. ``t_end``) that are not the same in every run."""
    runs = {}
    for path in paths:
        with xr.open_dataset(path) as ds:
            record = parameters(ds)
            runs[path] = {k: v for k, v in {**record.get("scene", {}), **record.get("solver", {})}.items()
                          if isinstance(v, (int, float, str, bool)) and k not in ("case", "progress")}
            runs[path].update(method=ds.attrs["method"], dx=float(ds.attrs["dx"]))
    keys = sorted({k for run in runs.values() for k in run})
    labels = {}
    for key in keys:
        values = [run.get(key) for run in runs.values()]
        if key not in ("method", "dx") and all(v == values[0] for v in values):
            continue
        numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values if v is not None)
        fill = float("nan") if numeric else ""
        labels[key] = {path: (fill if run.get(key) is None else run[key]) for path, run in runs.items()}
    return labels
