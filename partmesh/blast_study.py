"""The blast-array study of Prasanna Kumar, Patnaik & Ramamurthi (Phys.
Fluids 30, 046105, 2018; SPEC §4.2): which rigid rod array best shields a
wall from a blast, answered per method.

A study is a list of :class:`Configuration` (the no-obstacle channel and
rod arrays), run with every method as independent runs on Dask
(:func:`partmesh.sweeps.execute`: one netCDF file per run, finished runs
skipped, so a stopped study is finished by running it again), then
tabulated (:func:`partmesh.compare.report.wall_load_table`), ranked by wall impulse
per method with the rank correlation between methods, and drawn.

The arrays are computed on one row pitch across y and tiled onto the
3-row channel (``one_period``, tested equal to the full-width run); the
channel without obstacles is one-dimensional, so it runs as the 1D
``blast_wall`` with the channel's height (its wall force per metre depth
is ``(p_wall − p0) × 0.12 m``, comparable with the arrays').
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from partmesh.cases.blast import ARRANGEMENTS, ROW_PITCH
from partmesh.cases.errors import InputError
from partmesh.cases.registry import get
from partmesh.cases.shape_factories import SHAPES
from partmesh.compare import plots
from partmesh.compare.io import read
from partmesh.compare.report import (
    agreement,
    grid_convergence,
    rank_correlation,
    ranking,
    table,
    wall_load_table,
    write_table,
)
from partmesh.sweeps import SweepRun, execute, finished

#: the study's parts: the 11 moderate-blast configurations of the seed study's
#: first table; its staggered variants (layers, standoff, trap gap, the
#: strong blast); the inline variants recorded before them
PARTS = ("moderate", "layers", "standoff", "trap", "strong", "variants_inline")
#: the shapes the variants are run for (the seed study's best performers)
VARIANT_SHAPES = ("square", "triangle_right")
#: the trap: two sets of three layers 0.08 m apart, 0.17 m from the wall
TRAP = {"layers": 6, "trap_gap": 0.08, "standoff": 0.17}
#: the trap gaps of the ``trap`` part [m] (seed study, Fig. 14)
TRAP_GAPS = (0.02, 0.04, 0.08, 0.12, 0.16)
#: the array the variants change one thing of: 3 staggered layers, 0.34 m from the wall
BASE_LAYERS, BASE_STANDOFF = 3, 0.34
#: the time of the snapshots (seed study, Fig. 6)
SNAPSHOT_TIME = 1.7e-3
#: the wall loads compared between methods (:func:`partmesh.compare.report.agreement`)
AGREEMENT = ("wall_force_peak_raw", "wall_force_peak_fitted", "wall_impulse_final", "wall_arrival_time",
             "wall_peak_pressure_fitted")
ROWS = 3
#: the methods that run the strong-blast traps on the whole channel: sph's
#: supports in the trap's rarefied gas outgrow half a row pitch (the square
#: trap at 2 mm: H = 20 mm at t = 0.41 ms), which one pitch with periodic
#: images cannot hold
WHOLE_CHANNEL_STRONG = ("sph",)


@dataclass(frozen=True)
class Configuration:
    """One configuration of the study: a ``label`` for tables and figures
    and the scene (``case`` with ``parameters``) it runs; the methods of
    ``whole_channel`` run an array on the whole channel instead of one row
    pitch (``one_period`` false)."""
    label: str
    case: str
    parameters: tuple = ()
    part: str = "moderate"
    whole_channel: tuple = ()

    def run(self, method: str, dx: float | None = None) -> SweepRun:
        """The run of this configuration with ``method`` at ``dx`` (default:
        the scene's, named in the run either way, so a ladder through the
        default spacing finds the study's run finished)."""
        values = self.parameters
        if method in self.whole_channel:
            values = tuple((key, False if key == "one_period" else value) for key, value in values)
        return SweepRun(self.case, method, self.scene().dx if dx is None else float(dx), values)

    def scene(self):
        """The scene this configuration runs."""
        return get(self.case, **dict(self.parameters))


def _open_channel(blast: str, part: str) -> Configuration:
    return Configuration(f"no obstacle ({blast})", "blast_wall",
                         (("blast", blast), ("dim", 1), ("height", ROWS * ROW_PITCH)), part)


def _array(label: str, part: str, blast: str = "moderate", whole_channel=(), **parameters) -> Configuration:
    values = {"blast": blast, "rows": ROWS, "one_period": True, **parameters}
    return Configuration(label, "blast_array", tuple(values.items()), part, tuple(whole_channel))


def file_stem(label: str) -> str:
    """A configuration's label as a file name: ``no obstacle (moderate)``
    -> ``no_obstacle_moderate``."""
    return label.replace(" ", "_").replace("(", "").replace(")", "")


def _staggered(shape: str, label: str, part: str, blast: str = "moderate", whole_channel=(), layers=BASE_LAYERS,
               standoff=BASE_STANDOFF, **parameters) -> Configuration:
    """The staggered array of ``shape`` with the base array's layers and
    standoff changed as given; the scene parameters name only what differs
    from the base array, so the same array is the same run in every part
    (``square staggered`` of ``moderate`` is ``square staggered 3 layers``)."""
    changed = {"layers": layers} if layers != BASE_LAYERS else {}
    changed |= {"standoff": standoff} if standoff != BASE_STANDOFF else {}
    return _array(f"{shape} staggered {label}", part, blast, whole_channel, shape=shape, arrangement="staggered",
                  **changed, **parameters)


def configurations(parts=("moderate",)) -> list[Configuration]:
    """The configurations of the study's ``parts`` (:data:`PARTS`), the
    design of Prasanna Kumar et al. (2018), every variant staggered:

    * ``moderate``: no obstacle, and 3 layers of each shape inline and
      staggered at standoff 0.34 m (11 configurations);
    * ``layers``: 3, 5 and 7 staggered layers of the square and the
      right-facing triangle (:data:`VARIANT_SHAPES`) at 0.34 m;
    * ``standoff``: 3 layers at 0.17, 0.34 and 0.51 m, and 7 layers at 0.17 m;
    * ``trap``: two sets of three layers at 0.17 m, :data:`TRAP_GAPS`
      apart, beside the same six layers without a gap;
    * ``strong``: the strong blast on no obstacle and on the 0.08 m trap
      (:data:`TRAP`) of both shapes (on the whole channel for
      :data:`WHOLE_CHANNEL_STRONG`), to 2 ms;
    * ``variants_inline``: the inline variants recorded first (standoff
      0.17 and 0.51 m, 5 and 7 layers, the 0.08 m trap and its control, the
      strong traps).
    """
    unknown = [p for p in parts if p not in PARTS]
    if unknown or not parts:
        raise InputError(f"study part {unknown[0] if unknown else '(none)'!r} is not one of {', '.join(PARTS)}.")
    found = []
    if "moderate" in parts:
        found.append(_open_channel("moderate", "moderate"))
        found += [_array(f"{shape} {arrangement}", "moderate", shape=shape, arrangement=arrangement)
                  for shape in SHAPES for arrangement in ARRANGEMENTS]
    for shape in VARIANT_SHAPES:
        if "layers" in parts:
            found += [_staggered(shape, f"{n} layers", "layers", layers=n) for n in (3, 5, 7)]
        if "standoff" in parts:
            found += [_staggered(shape, f"standoff {s:g}", "standoff", standoff=s) for s in (0.17, 0.34, 0.51)]
            found.append(_staggered(shape, "7 layers standoff 0.17", "standoff", layers=7, standoff=0.17))
        if "trap" in parts:
            found.append(_staggered(shape, "6 layers standoff 0.17", "trap", layers=6, standoff=0.17))
            found += [_staggered(shape, f"trap {g:g}", "trap", layers=6, standoff=0.17, trap_gap=g)
                      for g in TRAP_GAPS]
    if "strong" in parts:
        found.append(_open_channel("strong", "strong"))
        found += [_staggered(shape, "trap (strong)", "strong", "strong", WHOLE_CHANNEL_STRONG, **TRAP)
                  for shape in VARIANT_SHAPES]
    if "variants_inline" in parts:
        for shape in VARIANT_SHAPES:
            # their scene parameters as first recorded (arrangement left at its default, inline)
            found += [_array(f"{shape} inline standoff {s:g}", "variants_inline", shape=shape, standoff=s)
                      for s in (0.17, 0.51)]
            found += [_array(f"{shape} inline {n} layers", "variants_inline", shape=shape, layers=n) for n in (5, 7)]
            found.append(_array(f"{shape} inline 6 layers standoff 0.17", "variants_inline", shape=shape, layers=6,
                                standoff=0.17))
            found.append(_array(f"{shape} inline trap", "variants_inline", shape=shape, **TRAP))
        found += [_array(f"{shape} inline trap (strong)", "variants_inline", blast="strong", shape=shape,
                         whole_channel=WHOLE_CHANNEL_STRONG, **TRAP) for shape in VARIANT_SHAPES]
    return found


def configuration(label: str) -> Configuration:
    """The configuration of any part of the study called ``label``."""
    every = {c.label: c for c in configurations(PARTS)}
    if label not in every:
        raise InputError(f"no configuration of the study is called {label!r}; they are: {', '.join(every)}.")
    return every[label]


def run_study(methods, parts=("moderate",), output: str | Path = "study", dx: dict | None = None,
              settings: dict | None = None, scheduler: str | None = None, workers: int | None = None,
              progress: bool = True, configs: list[Configuration] | None = None) -> pd.DataFrame:
    """Run every configuration of ``parts`` (or the given ``configs``) with every one of ``methods``
    (``dx``: method -> spacing, default each scene's) into
    ``output/runs/`` on Dask (:func:`partmesh.sweeps.execute`; ``settings`` go
    to the methods that take them; a run shared by two parts runs once),
    then write the report of :func:`report_study` of each part into
    ``output/<part>/``; returns the table of every part, with its ``part``."""
    dx = dict(dx or {})
    configs = configurations(parts) if configs is None else list(configs)
    runs = list(dict.fromkeys(c.run(method, dx.get(method)) for method in methods for c in configs))
    records = _reported(execute(runs, Path(output) / "runs", settings, scheduler, workers, progress,
                                "blast-array study"))
    seconds = {r["name"]: r["seconds"] for r in records if r["status"] == "ran"}
    tables = []
    for part in dict.fromkeys(c.part for c in configs):
        group = [c for c in configs if c.part == part]
        tables.append(report_study(group, methods, Path(output), dx, seconds, Path(output) / part)
                      .assign(part=part))
    return pd.concat(tables, ignore_index=True)


def _reported(records: list[dict]) -> list[dict]:
    """The records of :func:`partmesh.sweeps.execute`, after printing the runs that failed and why."""
    for r in records:
        if r["status"] == "failed":
            print(f"failed: {r['name']}: {r['message']}")
    return records


def report_study(configs, methods, output: Path, dx: dict | None = None, seconds: dict | None = None,
                 folder: Path | None = None) -> pd.DataFrame:
    """The report of ``configs`` from the finished runs in ``output/runs/``,
    written into ``folder`` (default ``output``):

    * ``wall_loads.csv``/``.json``/``.nc``: one row per configuration and
      method (:func:`partmesh.compare.report.wall_load_table`) with its blast;
    * ``ranking.csv``: the configurations of each blast ranked by wall
      impulse per method (1: the lowest impulse), ``rank_correlation.csv``:
      Spearman's ρ between the methods' rankings, per blast;
    * ``wall_time.csv``: per blast and method, the number of runs and
      their summed solver time (``wall_seconds``), JIT compile time
      (``compile_seconds``) and, with ``seconds``, the time the runs made
      now took (``run_seconds``);
    * ``agreement.csv`` (fv and another method): per configuration and
      method, the relative difference of the wall loads from fv's
      (:func:`partmesh.compare.report.agreement`);
    * figures: wall force and impulse of every configuration with its
      methods overlaid (``wall_force_<label>.png``), of every method and
      part of the study with its configurations overlaid
      (``wall_force_<method>_<part>.png``), and schlieren and density
      snapshots at 1.7 ms per method and part
      (``schlieren_<method>_<part>.png``, ``density_<method>_<part>.png``:
      the schlieren of a particle method's noisy density is mostly noise).

    Runs not finished are left out of the tables (listed as missing).
    ``seconds`` (run name -> seconds) adds the wall time the runs took
    here to the table's ``wall_seconds`` (solver time) as ``run_seconds``
    (NaN for a run not made now)."""
    dx = dict(dx or {})
    folder = output if folder is None else Path(folder)
    runs, labels, names, blasts, parts, missing = [], [], [], [], [], []
    for method in methods:
        for c in configs:
            name = c.run(method, dx.get(method)).name
            path = output / "runs" / f"{name}.nc"
            if finished(path):
                runs.append(read(path))
                labels.append(c.label)
                names.append(name)
                blasts.append(dict(c.parameters)["blast"])
                parts.append(c.part)
            else:
                missing.append(name)
    if not runs:
        raise InputError(f"no finished runs of the study in {str(output / 'runs')!r}.")
    table = wall_load_table(runs, labels)
    table.insert(1, "blast", blasts)
    if seconds is not None:
        table["run_seconds"] = [seconds.get(n, float("nan")) for n in names]
    write_table(table, folder, "wall_loads")
    impulse = "wall_impulse_final"
    # the configurations of each blast ranked among themselves
    ranks = {blast: ranking(group, impulse) for blast, group in table.groupby("blast", sort=False)}
    pd.concat(ranks, names=["blast"]).to_csv(folder / "ranking.csv")
    pd.concat({blast: rank_correlation(r) for blast, r in ranks.items()}, names=["blast"]).to_csv(
        folder / "rank_correlation.csv")
    timed = ["wall_seconds", "compile_seconds"] + (["run_seconds"] if seconds is not None else [])
    groups = table.groupby(["blast", "method"], sort=False)
    groups[timed].sum(min_count=1).assign(runs=groups.size()).to_csv(folder / "wall_time.csv")
    if "fv" in set(table["method"]) and table["method"].nunique() > 1:
        agreement(table, AGREEMENT).to_csv(folder / "agreement.csv", index=False)
    figures = folder / "figures"
    for label in dict.fromkeys(labels):
        group = [(ds, ds.attrs["method"]) for ds, lab in zip(runs, labels) if lab == label]
        stem = file_stem(label)
        for var in ("wall_force", "wall_impulse"):
            plots.series([g[0] for g in group], var, figures / f"{var}_{stem}.png", names=[g[1] for g in group],
                         scale=1e3, unit="ms", title=label)
    for method, part in dict.fromkeys((ds.attrs["method"], p) for ds, p in zip(runs, parts)):
        group = [(ds, lab) for ds, lab, p in zip(runs, labels, parts) if ds.attrs["method"] == method and p == part]
        for var in ("wall_force", "wall_impulse"):
            plots.series([g[0] for g in group], var, figures / f"{var}_{method}_{part}.png",
                         names=[g[1] for g in group], scale=1e3, unit="ms", title=f"{method}, {part}")
        maps = [(ds, lab) for ds, lab in group if "y" in ds.dims and SNAPSHOT_TIME <= float(ds.time[-1])]
        if maps:
            shown, titles = [m[0] for m in maps], [f"{method}: {m[1]}" for m in maps]
            plots.schlieren_maps(shown, figures / f"schlieren_{method}_{part}.png", names=titles,
                                 time=SNAPSHOT_TIME, columns=1)
            plots.field_maps(shown, "rho", figures / f"density_{method}_{part}.png", names=titles,
                             time=SNAPSHOT_TIME, columns=1)
    if any(c.part in TRENDS for c in configs):
        _trends(table, configs, folder)
    if missing:
        print(f"{len(missing)} runs not finished: {', '.join(missing)}")
    return table


#: the parts whose configurations differ in one number: that scene parameter and its axis label
TRENDS = {"layers": ("layers", "layers"), "standoff": ("standoff", "standoff [m]"), "trap": ("trap_gap", "trap gap [m]")}
#: the wall loads drawn against it, their labels and scales
TREND_QUANTITIES = {"wall_peak_overpressure_fitted": ("peak wall overpressure, fitted [kPa]", 1e-3),
                    "wall_force_peak_fitted": ("peak wall force, fitted [kN/m]", 1e-3),
                    "wall_force_peak_raw": ("peak wall force, raw [kN/m]", 1e-3),
                    "wall_impulse_final": ("wall impulse at 3 ms [N s/m]", 1.0)}


def _trends(table: pd.DataFrame, configs, folder: Path) -> None:
    """The wall loads of a part against the number its configurations
    differ in (layers, standoff, trap gap), every method and shape on one
    figure (``trend_<part>.png``) and as a table (``trend.csv``); for the
    layers, the change of each load from 3 to 5 and from 5 to 7 layers
    (``layer_reduction.csv``, relative to the fewer layers)."""
    by_label = {c.label: c for c in configs}
    rows = table[table["configuration"].isin(by_label)].copy()
    part = by_label[rows["configuration"].iloc[0]].part
    key, xlabel = TRENDS[part]
    scenes = {label: by_label[label].scene().parameters for label in rows["configuration"]}
    rows["shape"] = [scenes[label]["shape"] for label in rows["configuration"]]
    rows[key] = [scenes[label][key] for label in rows["configuration"]]
    rows["wall_peak_overpressure_fitted"] = rows["wall_peak_pressure_fitted"] - [scenes[label]["p0"]
                                                                                for label in rows["configuration"]]
    if part == "standoff":  # (the 7 layers at 0.17 m are compared with the 3 at 0.17 m in the table, not drawn)
        rows = rows[[scenes[label]["layers"] == BASE_LAYERS for label in rows["configuration"]]]
    quantities = list(TREND_QUANTITIES)
    rows[["configuration", "method", "shape", key] + quantities].to_csv(folder / "trend.csv", index=False)
    plots.trends(rows, key, quantities, folder / f"trend_{part}.png",
                 f"wall loads against {xlabel.split(' [')[0]} (staggered arrays)", xlabel,
                 {q: v[0] for q, v in TREND_QUANTITIES.items()}, {q: v[1] for q, v in TREND_QUANTITIES.items()})
    if part == "layers":
        changes = []
        for (method, shape), group in rows.groupby(["method", "shape"], sort=False):
            values = group.set_index(key)
            for n0, n1 in ((3, 5), (5, 7)):
                if n0 in values.index and n1 in values.index:
                    changes.append({"method": method, "shape": shape, "from": n0, "to": n1,
                                    **{q: values.loc[n1, q] / values.loc[n0, q] - 1.0 for q in quantities}})
        pd.DataFrame(changes).to_csv(folder / "layer_reduction.csv", index=False)


def run_sensitivity(ladders: dict, output: str | Path = "study", label: str = "circle inline",
                    settings: dict | None = None, scheduler: str | None = None, workers: int | None = None,
                    progress: bool = True) -> pd.DataFrame:
    """The resolution study of one configuration (the seed study's Table
    II): ``ladders`` maps each method to its spacings (three or more for a
    Grid Convergence Index), run into ``output/runs/`` on Dask, and
    written to ``output/sensitivity/``: the table of every run
    (``ladder.csv``/``.json``/``.nc``), the Richardson value and GCI of
    every wall-load quantity per method from its three finest levels
    (``convergence.csv``, Celik et al. 2008), and the speed-versus-error
    figures against the finest fv run (relative error of the wall impulse
    and of the fitted peak wall force against wall time, Pareto front
    marked). Returns the table."""
    config = configuration(label)
    runs = [config.run(method, dx) for method, spacings in ladders.items() for dx in spacings]
    records = _reported(execute(runs, Path(output) / "runs", settings, scheduler, workers, progress,
                                f"ladder of {label}"))
    done = [r for r in records if r["status"] != "failed"]
    if not done:
        raise InputError(f"no run of the ladder of {label!r} finished.")
    results = [read(r["path"]) for r in done]
    df = table(results, None, [r["name"] for r in done])
    quantities = [q for q in results[0].attrs.get("measured_quantities", "").split() if q in df]
    folder = Path(output) / "sensitivity"
    fv = df[df["method"] == "fv"]
    if not fv.empty:
        finest = fv.loc[fv["dx"].idxmin()]
        for q in ("wall_impulse_final", "wall_force_peak_fitted"):
            df[f"{q}_error"] = (df[q] - finest[q]).abs() / abs(finest[q])
            title = f"{label}: {q.replace('_', ' ')} against the finest fv run (dx = {finest['dx']:g} m)"
            plots.speed_versus_error(df, f"{q}_error", folder / f"speed_versus_error_{q}.png", title,
                                     ylabel=f"relative error of {q.replace('_', ' ')}")
    write_table(df, folder, "ladder")
    grid_convergence(df, quantities).to_csv(folder / "convergence.csv", index=False)
    return df
