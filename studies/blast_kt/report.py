"""The blast_kt record: shock radius, peak density and cost per method.

    python studies/blast_kt/report.py RUNS_FOLDER studies/blast_kt [--reference FILE]

Reads every ``blast_kt`` result in RUNS_FOLDER (one scene: the same yield and
quadrant) and writes beside this script

* ``runs.csv``: per run, method, spacing, settings, elements, solver time,
  its speedup over each other method at the same spacing (over that
  method's fastest run there), the solver time taken to each output time
  (``frame_seconds``), and the shock radius (with its error against the
  reference) and peak ring-averaged density at each output time;
* ``front.png``: shock radius against time (with Sedov–Taylor) and peak
  density against time; ``cost.png``: solver time against simulated time;
  ``centre_line.png``: density along the symmetry axis y = 0 at the last time;
  ``density.png``: the density field of every run at the last time.

The reference (``--reference``, default: the finest fv run) gives each run's
radius error. Radius and peak density are measured anew from each run's
fields (:func:`partmesh.cases.blast.blast_front`), so runs written before a change
of that measure are read alike.
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

from partmesh.cases.blast import KILOTON, blast_front  # noqa: E402
from partmesh.compare.exact.sedov import shock_radius  # noqa: E402
from partmesh.compare.io import read  # noqa: E402


def label(ds) -> str:
    """Method, spacing and the settings that set it apart."""
    solver = json.loads(ds.attrs["parameters"])["solver"]
    extra = [f"{k}={solver[k]}" for k in ("masses", "sensor", "threshold", "buffer") if k in solver]
    return " ".join([ds.attrs["method"], f"dx={ds.attrs['dx']:g} m", *extra])


def fronts(runs: dict) -> dict:
    """Shock radius and peak density per output time of each run, from its fields."""
    return {name: blast_front(ds, json.loads(ds.attrs["parameters"])["scene"]["p0"]) for name, ds in runs.items()}


def table(runs: dict, front: dict, reference: str) -> pd.DataFrame:
    """One row per run: cost, and front radius and peak density per output time."""
    R_ref = np.asarray(front[reference]["shock_radius"])
    rows = []
    for name, ds in runs.items():
        a = ds.attrs
        R, peak = np.asarray(front[name]["shock_radius"]), np.asarray(front[name]["peak_density"])
        row = {"run": name, "method": a["method"], "dx": a["dx"], "n_elements": a["n_elements"],
               "wall_seconds": a["wall_seconds"], "compile_seconds": a["compile_seconds"], "status": a["status"],
               "particles_max": a.get("particles_max", np.nan),
               "fluid_particles_max": a.get("fluid_particles_max", np.nan),
               "radius_error_final": R[-1] / R_ref[-1] - 1.0}
        # the speedup over each other method at the same spacing: its solver time (its fastest run's) over this one's
        for other in runs.values():
            key = f"speedup_over_{other.attrs['method']}"
            if other.attrs["method"] != a["method"] and np.isclose(other.attrs["dx"], a["dx"]):
                row[key] = min(row.get(key, np.inf), other.attrs["wall_seconds"] / a["wall_seconds"])
        for k, t in enumerate(ds.time.values):
            row[f"frame_seconds_{t * 1e3:g}ms"] = np.asarray(a.get("frame_seconds", np.full(ds.sizes["time"], np.nan)))[k]
            row[f"shock_radius_{t * 1e3:g}ms"] = R[k]
            row[f"radius_error_{t * 1e3:g}ms"] = R[k] / R_ref[k] - 1.0
            row[f"peak_density_{t * 1e3:g}ms"] = peak[k]
        rows.append(row)
    return pd.DataFrame(rows)


def figures(runs: dict, front: dict, out: Path) -> None:
    """front.png, cost.png and centre_line.png."""
    first = next(iter(runs.values()))
    scene = json.loads(first.attrs["parameters"])["scene"]
    t = np.linspace(0.0, float(first.time[-1]), 200)
    fig, (ax_r, ax_rho) = plt.subplots(1, 2, figsize=(11, 4))
    ax_r.plot(t * 1e3, shock_radius(t, scene["kt"] * KILOTON, scene["rho0"], scene["gamma"]), "k--",
              label="Sedov–Taylor (point blast)")
    fig_cost, ax_cost = plt.subplots(figsize=(5.5, 4))
    fig_line, ax_line = plt.subplots(figsize=(6, 4))
    for name, ds in runs.items():
        times = ds.time.values * 1e3
        ax_r.plot(times, front[name]["shock_radius"], "o-", label=name)
        ax_rho.plot(times, front[name]["peak_density"], "o-", label=name)
        if "frame_seconds" in ds.attrs:
            ax_cost.plot(times, ds.attrs["frame_seconds"], "o-", label=name)
        line = ds.rho.isel(time=-1).sel(y=0.0, method="nearest")
        ax_line.plot(line.x, line, label=name)
    ax_r.set(xlabel="t [ms]", ylabel="shock radius [m]")
    ax_rho.set(xlabel="t [ms]", ylabel="peak ring-averaged density [kg/m³]", yscale="log")
    ax_r.legend(fontsize=7, loc="upper left")
    ax_cost.set(xlabel="simulated time [ms]", ylabel="solver time [s]", yscale="log")
    ax_cost.legend(fontsize=7)
    ax_line.set(xlabel="x [m] (y = 0)", ylabel="density [kg/m³]",
                title=f"t = {float(first.time[-1]) * 1e3:g} ms")
    ax_line.legend(fontsize=7)
    columns = min(len(runs), 3)
    rows = -(-len(runs) // columns)
    fig_map, axes = plt.subplots(rows, columns, figsize=(3.4 * columns, 3.3 * rows), squeeze=False)
    top = max(float(ds.rho.isel(time=-1).max()) for ds in runs.values())
    for ax in axes.flat[len(runs):]:
        ax.set_visible(False)
    for ax, (name, ds) in zip(axes.flat, runs.items()):
        image = ax.pcolormesh(ds.x, ds.y, ds.rho.isel(time=-1).transpose("y", "x"), vmin=0.0, vmax=min(top, 10.0),
                              shading="auto")
        ax.set(aspect="equal", xlabel="x [m]", ylabel="y [m]")
        ax.set_title(name.replace(" sensor", "\nsensor"), fontsize=8)
    fig_map.colorbar(image, ax=axes, label=f"density at {float(first.time[-1]) * 1e3:g} ms [kg/m³]", shrink=0.6)
    for f, name in ((fig, "front.png"), (fig_cost, "cost.png"), (fig_line, "centre_line.png")):
        f.tight_layout()
        f.savefig(out / name, dpi=120)
        plt.close(f)
    fig_map.savefig(out / "density.png", dpi=120)
    plt.close(fig_map)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs")
    parser.add_argument("out")
    parser.add_argument("--reference", help="the run whose radii the others are compared with (default: the finest fv run)")
    args = parser.parse_args(argv)
    runs = {}
    for path in sorted(Path(args.runs).glob("*.nc")):
        ds = read(path)
        if ds.attrs["case"] == "blast_kt":
            runs[label(ds)] = ds
    fv = [name for name in runs if runs[name].attrs["method"] == "fv"]
    reference = args.reference or min(fv, key=lambda name: runs[name].attrs["dx"])
    out = Path(args.out)
    front = fronts(runs)
    table(runs, front, reference).to_csv(out / "runs.csv", index=False, float_format="%.6g")
    figures(runs, front, out)
    print(f"{len(runs)} runs; reference {reference}; wrote runs.csv, front.png, cost.png, centre_line.png, density.png")


if __name__ == "__main__":
    main()
