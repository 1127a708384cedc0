"""Make the reports of this record again from its stored runs, running nothing.

    python studies/blast_array/remake.py study/

Every stored run (``fv/runs``, ``sph/runs``, ``dsmc/runs``) is linked into
``study/runs/``, where ``partmesh study`` finds it finished, and each report
is written as ``partmesh study`` writes it (:func:`partmesh.blast_study.report_study`,
:func:`partmesh.blast_study.run_sensitivity`), into the folder of the record
that holds it:

* ``study/methods/``: the moderate part, fv, sph and dsmc at 1 mm
  (``partmesh study -m fv,sph,dsmc``);
* ``study/variants/``: the inline variants and the inline strong traps
  (part ``variants_inline``) with the strong blast's open channel, fv at
  1 mm, sph and dsmc at 2 mm;
* ``study/layers/``, ``standoff/``, ``trap/``, ``strong/``: the staggered
  parts, fv at 1 mm, sph and dsmc at 2 mm;
* ``study/sensitivity/``: the record's ``ladder/``, the ladders of the
  inline circles (``partmesh study --ladder fv=2e-3,1e-3,5e-4 --ladder
  sph=2e-3,1.414e-3,1e-3 --ladder dsmc=4e-3,2e-3,1e-3``).

A report whose runs are not all stored is refused before it is written
(a missing run would be made by ``partmesh study``, not here).

    python studies/blast_array/remake.py study/ --record

then brings the rows that :mod:`remeasure` changed into the record's tables,
and nothing else: the record's tables hold values of runs made before the
stored ones in places (fv runs made again by ``9cd18dc`` and ``9ec67d8``
that agree with them to round-off, an sph run of the strong open channel
that is not kept; the README says where), so each table is kept row by
row. In each row of ``wall_loads.csv`` (``ladder.csv``) the quantities its
stored run lists in ``remeasured_quantities`` are taken from the fresh
report, and the new ``wall_force_peak_mean`` is added where the stored run
is the row's own (the same steps and impulse) or the row's run made again
and agreeing with it (impulse within 0.2 %: fv's made again by ``9cd18dc``
and ``9ec67d8``), NaN where it is neither (sph's strong open channel);
``ranking.csv``, ``rank_correlation.csv``, ``agreement.csv``, ``trend.csv``,
``layer_reduction.csv`` and ``trend_<part>.png`` are made again from the
merged table by the study's functions, the ladder's ``convergence.csv``
rows of dsmc and of the new quantity and its speed-versus-error figures
from the fresh report. ``variants/`` takes today's labels of its
configurations (``square inline trap (strong)`` for ``square trap
(strong)``). Figures of the histories do not change and are left.
"""

from __future__ import annotations

import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from partmesh.blast_study import AGREEMENT, _trends, configurations, report_study, run_sensitivity
from partmesh.compare.io import read
from partmesh.compare.report import agreement, rank_correlation, ranking
from partmesh.sweeps import finished

HERE = Path(__file__).parent
METHODS = ("fv", "sph", "dsmc")
#: each report of the record: its configurations and the spacing of each method (None: the scene's, 1 mm)
REPORTS = {
    "methods": (lambda: configurations(("moderate",)), {}),
    "variants": (lambda: configurations(("variants_inline",)) + [c for c in configurations(("strong",))
                                                                 if c.case == "blast_wall"],
                 {"sph": 2e-3, "dsmc": 2e-3}),
    **{part: ((lambda part=part: configurations((part,))), {"fv": 1e-3, "sph": 2e-3, "dsmc": 2e-3})
       for part in ("layers", "standoff", "trap", "strong")},
}
#: the ladders of the inline circles, per method
LADDERS = {"fv": (2e-3, 1e-3, 5e-4), "sph": (2e-3, 1.414e-3, 1e-3), "dsmc": (4e-3, 2e-3, 1e-3)}


def link_runs(runs: Path) -> None:
    """Link every stored run of the record into ``runs``."""
    runs.mkdir(parents=True, exist_ok=True)
    for method in METHODS:
        for path in sorted((HERE / method / "runs").glob("*.nc")):
            link = runs / path.name
            if not link.exists():
                link.symlink_to(path.resolve())


def missing(output: Path, names) -> list[str]:
    """The runs of ``names`` that ``output/runs`` does not hold finished."""
    return [n for n in names if not finished(output / "runs" / f"{n}.nc")]


def main(output: str) -> None:
    output = Path(output)
    link_runs(output / "runs")
    for folder, (configs, dx) in REPORTS.items():
        configs = configs()
        absent = missing(output, [c.run(m, dx.get(m)).name for m in METHODS for c in configs])
        if absent:
            sys.exit(f"{folder}: {len(absent)} runs are not stored: {', '.join(absent)}")
        (output / folder).mkdir(parents=True, exist_ok=True)
        report_study(configs, METHODS, output, dx, folder=output / folder)
        print(f"{folder}: {len(configs)} configurations")
    circle = next(c for c in configurations(("moderate",)) if c.label == "circle inline")
    absent = missing(output, [circle.run(m, dx).name for m, spacings in LADDERS.items() for dx in spacings])
    if absent:
        sys.exit(f"ladder: {len(absent)} runs are not stored: {', '.join(absent)}")
    run_sensitivity({m: list(s) for m, s in LADDERS.items()}, output, "circle inline", progress=False)
    print(f"ladder: written to {output / 'sensitivity'}")


#: the quantities a run gets where it had none (:mod:`remeasure`)
NEW = ("wall_force_peak_mean",)


#: a stored run made again after the table's row was (the same scene and method) stands for the row's own run in
#: the new quantities where their impulses agree to this (fv runs made again by 9cd18dc and 9ec67d8: to 0.1 %)
AGAIN = 2e-3


def _own(row, attrs) -> bool:
    """Whether the stored run whose ``attrs`` are given made the table's ``row``: the same steps and impulse."""
    return int(row["n_steps"]) == int(attrs["n_steps"]) and math.isclose(
        row["wall_impulse_final"], attrs["wall_impulse_final"], rel_tol=1e-6)


def _again(row, attrs) -> bool:
    """Whether the stored run is the row's made again, agreeing with it to :data:`AGAIN` in impulse."""
    return math.isclose(row["wall_impulse_final"], attrs["wall_impulse_final"], rel_tol=AGAIN)


def _label(label: str, labels) -> str:
    """``label`` as today's configurations call it (an inline variant recorded as ``square trap`` is
    ``square inline trap``)."""
    if label in labels:
        return label
    shape, rest = label.split(" ", 1)
    return f"{shape} inline {rest}"


def merged(old: pd.DataFrame, fresh: pd.DataFrame, names, runs: Path, keys) -> tuple[pd.DataFrame, list[str]]:
    """``old`` (a record table) with, row by row, the quantities the row's
    stored run (``names``: run name per row) lists as re-measured taken from
    ``fresh`` (matched on ``keys``), and the new quantities where the
    stored run is the row's own; returns the table and what it did."""
    out, notes = old.copy(), []
    index = fresh.set_index(keys)
    for q in NEW:
        out[q] = np.nan
    for i, row in old.iterrows():
        attrs = read(runs / f"{names[i]}.nc").attrs
        new = index.loc[tuple(row[k] for k in keys) if len(keys) > 1 else row[keys[0]]]
        moved = [q for q in attrs.get("remeasured_quantities", "").split() if q not in NEW]
        if moved and not _own(row, attrs):
            raise SystemExit(f"{names[i]}: re-measured, but the table's row is not of this run")
        for q in moved + [f"{q}_error" for q in moved if f"{q}_error" in out.columns]:  # (and what is read off it)
            out.loc[i, q] = new[q]
        if _own(row, attrs) or _again(row, attrs):
            for q in NEW:
                out.loc[i, q] = new[q]
        if not _own(row, attrs):
            notes.append(f"{' '.join(str(row[k]) for k in keys)}: the stored run is not the row's own "
                         f"({int(row['n_steps'])} steps, impulse {row['wall_impulse_final']:.6g}; stored "
                         f"{int(attrs['n_steps'])}, {attrs['wall_impulse_final']:.6g}): {', '.join(NEW)} "
                         + ("from the stored run" if _again(row, attrs) else "left NaN"))
        if moved:
            notes.append(f"{' '.join(str(row[k]) for k in keys)}: " + ", ".join(
                f"{q} {row[q]:.6g} -> {new[q]:.6g}" for q in moved))
    columns = [c for c in fresh.columns if c in out.columns] + [c for c in out.columns if c not in fresh.columns]
    return out[columns], notes


def record(output: str) -> None:
    """Bring the re-measured rows of the fresh reports in ``output`` into the record (see the module's docstring)."""
    output = Path(output)
    runs = output / "runs"
    for folder, (configs, dx) in REPORTS.items():
        configs = configs()
        labels = {c.label: c for c in configs}
        old = pd.read_csv(HERE / folder / "wall_loads.csv")
        old["configuration"] = [_label(lab, labels) for lab in old["configuration"]]
        names = [labels[lab].run(m, dx.get(m)).name for lab, m in zip(old["configuration"], old["method"])]
        fresh = pd.read_csv(output / folder / "wall_loads.csv")
        table, notes = merged(old, fresh, names, runs, ["configuration", "method"])
        target = HERE / folder
        table.to_csv(target / "wall_loads.csv", index=False)
        ranks = {blast: ranking(group, "wall_impulse_final") for blast, group in table.groupby("blast", sort=False)}
        pd.concat(ranks, names=["blast"]).to_csv(target / "ranking.csv")
        pd.concat({blast: rank_correlation(r) for blast, r in ranks.items()}, names=["blast"]).to_csv(
            target / "rank_correlation.csv")
        agreement(table, AGREEMENT).to_csv(target / "agreement.csv", index=False)
        if folder in ("layers", "standoff", "trap"):
            _trends(table, configs, target)
        print(f"{folder}:", *notes, sep="\n  ")
    old = pd.read_csv(HERE / "ladder" / "ladder.csv")
    fresh = pd.read_csv(output / "sensitivity" / "ladder.csv")
    table, notes = merged(old, fresh, list(old["run"]), runs, ["run"])
    # the ladder's stored runs are the record's: the fresh report is the merged table, figures and all
    common = [c for c in fresh.columns if fresh[c].dtype.kind == "f"]
    same = np.allclose(table[common].to_numpy(float), fresh.set_index("run").loc[table["run"], common].to_numpy(float),
                       rtol=1e-12, equal_nan=True)
    if not same:
        raise SystemExit("ladder: the fresh ladder differs from the record beyond the re-measured rows")
    table.to_csv(HERE / "ladder" / "ladder.csv", index=False)
    convergence = pd.read_csv(output / "sensitivity" / "convergence.csv")
    kept = pd.read_csv(HERE / "ladder" / "convergence.csv")
    remade = (convergence["method"] == "dsmc") | convergence["quantity"].isin(NEW)
    kept = kept[~((kept["method"] == "dsmc") | kept["quantity"].isin(NEW))]
    rows = pd.concat([kept, convergence[remade]]).set_index(["method", "quantity"])
    order = list(convergence.set_index(["method", "quantity"]).index)
    rows.loc[[k for k in order if k in rows.index]].reset_index().to_csv(HERE / "ladder" / "convergence.csv",
                                                                          index=False)
    for figure in (output / "sensitivity").glob("speed_versus_error_*.png"):
        shutil.copyfile(figure, HERE / "ladder" / figure.name)
    print("ladder:", *notes, sep="\n  ")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[2] == "--record":
        record(sys.argv[1])
    elif len(sys.argv) == 2:
        main(sys.argv[1])
    else:
        sys.exit(__doc__.split("\n\n")[1])
