"""The surface_burst record: every run's ground gauges against Kingery–Bulmash.

    python studies/surface_burst/report.py RUNS_FOLDER studies/surface_burst

Reads every ``surface_burst`` and ``surface_burst_1d`` result in RUNS_FOLDER
(one charge mass) and writes beside this script

* ``gauges.csv``: per run and gauge, the peak overpressure (raw, and
  fitted behind the shock and carried back to it by the equal-area rule),
  arrival time, positive duration and impulse, the
  Kingery–Bulmash value of each and the ratio to it, with the run's method,
  geometry, cell size, cells and solver time;
* ``peaks.png``: peak overpressure (raw and fitted) and positive impulse
  against scaled distance on log axes, the Kingery–Bulmash curves and every run;
* ``histories.png``: overpressure at every gauge, every run overlaid;
* ``schlieren.png``: a numerical schlieren of the r–z runs (the quadrant's
  lower left quarter) at 10 ms W^(1/3), the front between the gauges Z3
  and Z5 (of a dsmc run its density: its schlieren is that of its scatter).

The gauge values are measured anew from each run's probe series
(:func:`partmesh.cases.charges.gauge_metrics`), so runs written before a
change of that measure are read alike.

    python studies/surface_burst/report.py --add RUNS_FOLDER studies/surface_burst

adds the runs in RUNS_FOLDER to the record instead: their rows replace
those of runs of the same name in ``gauges.csv`` (in their place) and
join the others in order, ``peaks.png`` is redrawn from the whole table,
and the figures that need a run's series and fields are drawn for each
added run alone, as ``histories_<file label>.png`` and, of an r–z run,
``schlieren_<file label>.png`` (:func:`file_label`: ``dsmc_rz_2cm``);
``histories.png`` and ``schlieren.png`` keep the runs they were drawn of.

A run that ends early (stopped, or ``--t-end`` short of the default) reads
NaN at a gauge whose blast it has not seen: the peaks (raw and fitted) and
the arrival where it ends before the Kingery–Bulmash arrival plus a
quarter of the positive phase (the maximum of a record the blast has not
reached is not its peak; of a dsmc record, it is its scatter's), the
duration and impulse where it ends before that phase is over.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from partmesh.cases.charges import GAUGE_QUANTITIES, gauge_metrics  # noqa: E402
from partmesh.cases.registry import method  # noqa: E402
from partmesh.compare.exact.kingery_bulmash import scaled_value  # noqa: E402
from partmesh.compare.io import read  # noqa: E402
from partmesh.compare.metrics import schlieren  # noqa: E402


def label(ds) -> str:
    """Method, geometry and cell size, and a dsmc redraw's profile where it is not the default."""
    shape = "1D sphere" if ds.attrs["geometry"] == "spherical" else "r-z"
    return f"{ds.attrs['method']} {shape} dx={ds.attrs['dx']:g} m" + "".join(f" {v}" for v in variant(ds))


def file_label(ds) -> str:
    """:func:`label` as a file name: ``dsmc_rz_2cm``, ``fv_1d_4mm``, ``fv_1d_2p5mm``, ``dsmc_rz_2cm_linear``,
    ``dsmc_rz_2cm_linear_seed2``."""
    mm = round(ds.attrs["dx"] * 1e3, 6)
    size = (f"{mm / 10:g}cm" if mm >= 10 else f"{mm:g}mm").replace(".", "p")
    shape = "1d" if ds.attrs["geometry"] == "spherical" else "rz"
    return "_".join([ds.attrs["method"], shape, size, *variant(ds)])


def variant(ds) -> list:
    """The settings of a run that set it apart from the record's other runs at its cell size: a TNT charge
    with JWL products (``jwl``) rather than a Brode balloon, a dsmc redraw's
    ``profile`` other than uniform, its ``redraw`` schedule other than every step, and a seed other than 1
    (every run of the record before it used seed 1); an fv run's refinement levels (``levels5``)."""
    parameters = json.loads(ds.attrs["parameters"])
    solver = parameters["solver"]
    jwl = ["jwl"] if parameters["scene"].get("charge", "balloon") == "jwl" else []
    profile = [solver["profile"]] if solver.get("profile", "uniform") != "uniform" else []
    redraw = [solver["redraw"]] if solver.get("redraw", "every-step") != "every-step" else []
    levels = [f"levels{solver['levels']}"] if solver.get("levels", 1) > 1 else []
    return jwl + levels + profile + redraw + ([f"seed{solver['seed']}"] if solver.get("seed", 1) != 1 else [])


def place(geometry: str, dx: float, before: float = 0.0) -> tuple:
    """A run's place in the record: by geometry, coarsest first, then by
    ``before`` (its row in the record it already has a place in)."""
    return geometry, -dx, before


def charge(ds) -> tuple[float, float]:
    """The run's charge mass W [kg] and ambient pressure p0 [Pa]."""
    scene = json.loads(ds.attrs["parameters"])["scene"]
    return scene["W"], scene["p0"]


def table(runs: dict) -> pd.DataFrame:
    """One row per run and gauge (see the module docstring)."""
    rows = []
    for name, ds in runs.items():
        W, p0 = charge(ds)
        values = gauge_metrics(ds, W, p0)
        t_last = float(ds.t_probe[-1])
        for gauge, x in zip(ds.probe.values, ds.probe_x.values):
            arrival, duration = values[f"{gauge}_arrival_time_kb"], values[f"{gauge}_positive_duration_kb"]
            seen = {q: t_last >= arrival + (duration if q.startswith("positive") else 0.25 * duration)
                    for q in GAUGE_QUANTITIES}
            row = {"run": name, "method": ds.attrs["method"], "geometry": ds.attrs["geometry"], "dx": ds.attrs["dx"],
                   "cells": ds.attrs["n_elements"], "wall_seconds": ds.attrs["wall_seconds"], "gauge": gauge,
                   "Z": x / W ** (1.0 / 3.0)}
            for q in GAUGE_QUANTITIES:
                row[q] = values[f"{gauge}_{q}"] if seen[q] else float("nan")
                kb = values[f"{gauge}_{q.replace('_fitted', '')}_kb"]
                row[f"{q}_kb"], row[f"{q}_ratio"] = kb, row[q] / kb
            rows.append(row)
    return pd.DataFrame(rows)


#: a colour map per method, geometry and charge (True: TNT with JWL products): its runs take shades of it,
#: finest darkest
FAMILIES = {("fv", "axisymmetric", False): "Blues", ("fv", "spherical", False): "Greens",
            ("sph", "axisymmetric", False): "Oranges", ("dsmc", "axisymmetric", False): "Purples",
            ("fv", "spherical", True): "Reds", ("fv", "axisymmetric", True): "RdPu",
            ("sph", "axisymmetric", True): "YlOrBr"}
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">")


def run_styles(df: pd.DataFrame) -> dict:
    """Per run, its line's colour (a shade of its method's, geometry's and
    charge's colour map, darker with a finer cell), marker (one per run of the family)
    and line style (dashed: refined), so no two runs look alike."""
    styles = {}
    jwl = df.run.str.split().apply(lambda words: "jwl" in words).rename("jwl")
    for (m, geometry, products), rows in df.groupby(["method", "geometry", jwl], sort=False):
        runs = list(rows.sort_values("dx", ascending=False, kind="stable").run.drop_duplicates())
        cmap = plt.get_cmap(FAMILIES.get((m, geometry, bool(products)), "Greys"))
        for k, run in enumerate(runs):
            styles[run] = dict(color=cmap(0.4 + 0.55 * k / max(len(runs) - 1, 1)), marker=MARKERS[k % len(MARKERS)],
                               ls="--" if "levels" in run else "-")
    return styles


def peaks_figure(df: pd.DataFrame, path: Path) -> None:
    """Peak overpressure (raw and fitted) and positive impulse against Z, with the Kingery–Bulmash curves."""
    Z = np.geomspace(0.4, 24.0, 200)
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.4))
    for ax, (q, kb, unit, scale) in zip(axes, (("peak_overpressure", "incident_overpressure", "kPa", 1e-3),
                                               ("peak_overpressure_fitted", "incident_overpressure", "kPa", 1e-3),
                                               ("positive_impulse", "incident_impulse", "Pa s", 1.0))):
        ax.loglog(Z, scaled_value(kb, Z) * scale, "k-", lw=2, label="Kingery-Bulmash (Swisdak 1994)")
        styles = run_styles(df)
        for run, rows in df.groupby("run", sort=False):
            ax.loglog(rows.Z, rows[q] * scale, ms=4, lw=1, label=run, **styles[run])
        ax.set_xlabel("scaled distance Z [m/kg^(1/3)]")
        ax.set_ylabel(f"{q.replace('_', ' ')} [{unit}]" + (" (per kg^(1/3))" if "impulse" in q else ""))
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def histories_figure(runs: dict, path: Path) -> None:
    """Overpressure at every gauge, every run overlaid."""
    gauges = list(next(iter(runs.values())).probe.values)
    fig, axes = plt.subplots(len(gauges), 1, figsize=(8, 2.0 * len(gauges)))
    for ax, gauge in zip(np.atleast_1d(axes), gauges):
        for name, ds in runs.items():
            _, p0 = charge(ds)
            p = ds["p_probe"].sel(probe=gauge)
            ax.plot(p.t_probe * 1e3, (p - p0) * 1e-3, lw=1, label=name)
        ax.set_ylabel(f"{gauge} [kPa]")
        ax.grid(True, alpha=0.3)
    np.atleast_1d(axes)[-1].set_xlabel("t [ms]")
    np.atleast_1d(axes)[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def schlieren_figure(runs: dict, path: Path, t: float) -> None:
    """A numerical schlieren of every r–z run at the output time nearest
    ``t``; of a stochastic method's run (dsmc), whose schlieren is the
    gradient of its scatter and shows nothing else, the density itself."""
    planes = {name: ds for name, ds in runs.items() if ds.attrs["geometry"] == "axisymmetric"}
    if not planes:
        return
    fig, axes = plt.subplots(1, len(planes), figsize=(4.5 * len(planes), 4.2), squeeze=False)
    for ax, (name, ds) in zip(axes[0], planes.items()):
        frame = ds["rho"].sel(time=t, method="nearest")
        if method(ds.attrs["method"]).takes_seed:
            shown = ax.pcolormesh(ds.x, ds.y, frame, cmap="viridis", shading="auto", vmin=0.5 * float(frame.median()),
                                  vmax=2.0 * float(frame.median()))
            fig.colorbar(shown, ax=ax, shrink=0.8, label="density [kg/m³]")
        else:
            ax.pcolormesh(ds.x, ds.y, schlieren(frame), cmap="gray", shading="auto")
        ax.set_aspect("equal")
        ax.set_xlim(0.0, 0.5 * float(ds.x[-1]))
        ax.set_ylim(0.0, 0.5 * float(ds.y[-1]))
        ax.set_title(f"{name}\nt = {float(frame.time) * 1e3:.3g} ms", fontsize=8)
        ax.set_xlabel("r [m]")
        ax.set_ylabel("z [m]")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--add", action="store_true",
                        help="add the runs to the record's gauges.csv instead of writing it anew (module docstring)")
    args = parser.parse_args(argv)
    found = {}
    for path in sorted(args.runs.glob("*.nc")):
        ds = read(path)
        if ds.attrs["case"] in ("surface_burst", "surface_burst_1d"):
            if label(ds) in found:
                parser.error(f"two runs in {args.runs} are both '{label(ds)}' ({path.name} and another): keep one")
            found[label(ds)] = ds
    if not found:
        parser.error(f"no surface_burst or surface_burst_1d result in {args.runs}")
    runs = dict(sorted(found.items(), key=lambda kv: place(kv[1].attrs["geometry"], kv[1].attrs["dx"])))
    df = table(runs)
    args.out.mkdir(parents=True, exist_ok=True)
    W = charge(next(iter(runs.values())))[0]
    front_time = 1e-2 * W ** (1.0 / 3.0)
    if args.add:
        record = args.out / "gauges.csv"
        if not record.is_file():
            parser.error(f"--add needs the record's {record}; without --add the record is written anew")
        kept = pd.read_csv(record)
        first_row = {run: i for i, run in reversed(list(enumerate(kept.run)))}
        df = pd.concat([kept[~kept.run.isin(list(runs))], df], ignore_index=True)
        key = {run: place(rows.geometry.iloc[0], rows.dx.iloc[0], first_row.get(run, len(kept)))
               for run, rows in df.groupby("run", sort=False)}
        df = df.sort_values("run", key=lambda run: run.map(key), kind="stable", ignore_index=True)
        for name, ds in runs.items():
            histories_figure({name: ds}, args.out / f"histories_{file_label(ds)}.png")
            schlieren_figure({name: ds}, args.out / f"schlieren_{file_label(ds)}.png", front_time)
    else:
        histories_figure(runs, args.out / "histories.png")
        schlieren_figure(runs, args.out / "schlieren.png", front_time)
    df.to_csv(args.out / "gauges.csv", index=False, float_format="%.6g")
    peaks_figure(df, args.out / "peaks.png")
    for q in ("peak_overpressure", "peak_overpressure_fitted"):
        print(f"{q} over Kingery–Bulmash")
        print(df.pivot_table(index="gauge", columns="run", values=f"{q}_ratio", sort=False, dropna=False).round(3)
              .to_string())


if __name__ == "__main__":
    main()
