"""Comparison tables: runs of one scene against a reference (SPEC §5).

:func:`table` turns runs (schema Datasets) and a reference (an exact
solution or another run) into one row per run: method, resolution, cost,
the L1/L2/L∞ error of every common field at the last common output time,
and the scalar quantities the scene measured (shock angle, C_R, wall load).
:func:`write_table` saves it as ``summary.csv`` and ``summary.json``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from partmesh.compare import plots
from partmesh.compare.convergence import gci
from partmesh.compare.metrics import field_error
from partmesh.compare.schema import FIELDS, parameters

COST_ATTRS = ("dx", "n_elements", "n_steps", "wall_seconds", "compile_seconds")
NORMS = ("L1", "L2", "Linf")


class IncompatibleResults(ValueError):
    """Results that cannot be compared: different scenes or different grids."""


def scene_of(ds: xr.Dataset) -> dict:
    """The scene parameters a result was computed for."""
    return parameters(ds).get("scene", {"case": ds.attrs["case"]})


def check_same_scene(runs: list[xr.Dataset], names: list[str]) -> None:
    """Refuse, in one sentence, runs of different scenes or on different output grids."""
    first = scene_of(runs[0])
    for ds, name in zip(runs[1:], names[1:]):
        other = scene_of(ds)
        if other != first:
            changed = sorted(k for k in set(first) | set(other) if first.get(k) != other.get(k))
            raise IncompatibleResults(
                f"{name} is a run of a different scene than {names[0]} (they differ in {', '.join(changed)})."
            )
        for coord in ("x", "y"):
            if (coord in ds.coords) != (coord in runs[0].coords) or (
                coord in ds.coords and not np.allclose(ds[coord].values, runs[0][coord].values, rtol=0, atol=1e-12)
            ):
                raise IncompatibleResults(f"{name} is not on the same output grid as {names[0]} (coordinate {coord}).")


def measured(ds: xr.Dataset) -> dict:
    """Scalar measurements a scene attached to the result (numeric attrs
    outside the schema's bookkeeping)."""
    skip = set(COST_ATTRS) | {"partmesh_version", "Conventions", "created"}
    return {k: float(v) for k, v in ds.attrs.items()
            if k not in skip and isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)}


def table(runs: list[xr.Dataset], reference: xr.Dataset | None = None, names: list[str] | None = None) -> pd.DataFrame:
    """One row per run: cost, field errors against ``reference`` at the last
    output time both hold, and the scene's measured quantities; last, a row
    ``reference`` with the quantities measured on the reference, if it
    carries any (:func:`partmesh.reporting.exact_reference` measures the exact
    solution where the scene can)."""
    names = names or [f"run{i}" for i in range(len(runs))]
    check_same_scene(runs, names)
    rows = []
    for ds, name in zip(runs, names):
        row = _cost_row(ds, name)
        if reference is not None:
            common = np.intersect1d(np.round(ds.time.values, 12), np.round(reference.time.values, 12))
            if common.size:
                t = common[-1]
                for field in (f for f in FIELDS if f in ds and f in reference):
                    a = ds[field].sel(time=t, method="nearest")
                    b = reference[field].sel(time=t, method="nearest")
                    for norm in NORMS:
                        row[f"{field}_{norm}"] = field_error(a, b, norm=norm)
                row["error_time"] = float(t)
        row.update(measured(ds))
        rows.append(row)
    if reference is not None and measured(reference):
        # the reference's own measured values (the exact ones, where the scene could measure its exact solution)
        rows.append({"run": "reference", "method": reference.attrs.get("method", "reference"),
                     **measured(reference)})
    return pd.DataFrame(rows)


def _cost_row(ds: xr.Dataset, name: str) -> dict:
    """The start of a run's table row: its name, method, scheme, cost and status."""
    row = {"run": name, "method": ds.attrs["method"], "scheme": ds.attrs["scheme"]}
    row.update({k: ds.attrs[k] for k in COST_ATTRS})
    row["status"] = ds.attrs.get("status", "ok")
    return row


def wall_load_table(runs: list[xr.Dataset], labels: list[str]) -> pd.DataFrame:
    """One row per run of a blast study (runs of different scenes, e.g. a
    channel with and without obstacles): its configuration ``label``,
    method, cost, the final time and the wall-load quantities the scene
    measured (peak wall pressure and force, raw and fitted, arrival time,
    wall impulse at the final time)."""
    rows = []
    for ds, label in zip(runs, labels):
        row = {"configuration": label, **_cost_row(ds, label), "t_end": _end_time(ds)}
        row.update({k: v for k, v in measured(ds).items() if k.startswith("wall_")})
        rows.append(row)
    return pd.DataFrame(rows).drop(columns="run")


def _end_time(ds: xr.Dataset) -> float:
    """The time a run reached: the last of its output frames and of its
    probe series (a run kept with one frame still holds its series whole)."""
    return max(float(ds[t][-1]) for t in ("time", "t_probe") if t in ds.coords)


def ranking(df: pd.DataFrame, quantity: str, item: str = "configuration") -> pd.DataFrame:
    """Rank of every ``item`` by ``quantity`` per method (1: the smallest
    value; ties share the lowest rank), items as rows and methods as
    columns; an item a method did not run is NaN."""
    values = df.pivot_table(index=item, columns="method", values=quantity, aggfunc="first", sort=False)
    return values.rank(method="min")


def agreement(df: pd.DataFrame, quantities, reference: str = "fv", item: str = "configuration") -> pd.DataFrame:
    """The relative difference (q_method − q_reference)/|q_reference| of
    each of ``quantities`` between every other method of ``df`` (a
    :func:`wall_load_table`) and the ``reference`` method, per ``item``
    both ran: one row per item and method, a column per quantity, and
    ``largest``, the largest magnitude among them. Empty if the reference
    method ran nothing."""
    columns = [item, "method", *quantities, "largest"]
    if reference not in set(df["method"]):
        return pd.DataFrame(columns=columns)
    values = df.pivot_table(index=item, columns="method", values=list(quantities), aggfunc="first", sort=False,
                            dropna=False)
    methods = [m for m in dict.fromkeys(df["method"]) if m != reference]
    rows = []
    for label in values.index:
        for method in methods:
            diff = {q: (values.loc[label, (q, method)] - values.loc[label, (q, reference)])
                    / abs(values.loc[label, (q, reference)]) for q in quantities}
            if all(np.isnan(v) for v in diff.values()):
                continue
            rows.append({item: label, "method": method, **diff, "largest": np.nanmax(np.abs(list(diff.values())))})
    return pd.DataFrame(rows, columns=columns)


def rank_correlation(ranks: pd.DataFrame) -> pd.DataFrame:
    """Spearman's rank correlation between the columns (methods) of a
    :func:`ranking`, each pair over the items both ranked (at least three):
    ρ = 1 − 6 Σ d²/(n(n² − 1)) without ties, the correlation of the ranks in general."""
    return ranks.corr(method="spearman", min_periods=3)


def grid_convergence(df: pd.DataFrame, quantities) -> pd.DataFrame:
    """Richardson value and Grid Convergence Index of each of ``quantities``
    (columns of ``df``, a :func:`table`) per method, from the method's three
    finest resolutions among its finished runs (Celik et al. 2008, by
    :func:`partmesh.compare.convergence.gci`; refinement ratios from ``dx``). One row
    per method and quantity: the levels ``dx1 < dx2 < dx3`` and values
    ``f1, f2, f3``, then p, ``f_ext`` (the Richardson value), ``gci_fine``
    and the rest of :func:`~partmesh.compare.convergence.gci`; where the three values
    give no observed order or do not converge (|ε₂₁/ε₃₂| ≥ 1), ``note``
    says why. Quantities
    equal on all three levels (a scene's exact value, not computed) and
    methods with fewer than three resolutions have no row."""
    rows = []
    finished = df[df["status"] == "ok"] if "status" in df else df
    for method, group in finished.groupby("method", sort=False):
        levels = group.drop_duplicates("dx").sort_values("dx").head(3)
        if len(levels) < 3:
            continue
        h1, h2, h3 = levels["dx"]
        for quantity in (q for q in quantities if q in levels):
            f1, f2, f3 = (float(v) for v in levels[quantity])
            if not np.all(np.isfinite([f1, f2, f3])) or f1 == f2 == f3:
                continue
            row = dict(method=method, quantity=quantity, dx1=h1, dx2=h2, dx3=h3, f1=f1, f2=f2, f3=f3)
            try:
                row.update(gci(f1, f2, f3, h2 / h1, h3 / h2))
                if not abs(row["convergence_ratio"]) < 1.0:
                    row["note"] = (f"the levels do not converge: the change from dx2 to dx1 is "
                                   f"{row['convergence_ratio']:.3g} times the change from dx3 to dx2.")
            except ValueError as err:
                row["note"] = str(err)
            rows.append(row)
    return pd.DataFrame(rows)


def write_table(df: pd.DataFrame, folder: str | Path, stem: str = "summary") -> Path:
    """Write ``<stem>.csv``, ``<stem>.json`` and ``<stem>.nc`` (the table
    as a Dataset on the dimension ``run``) into ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    df.to_csv(folder / f"{stem}.csv", index=False)
    (folder / f"{stem}.json").write_text(json.dumps(df.to_dict(orient="records"), indent=2, default=float))
    table_ds = xr.Dataset({c: ("run", df[c].to_numpy(dtype=str if df[c].dtype == object else None)) for c in df})
    table_ds.to_netcdf(folder / f"{stem}.nc")
    return folder


def _views(runs, reference) -> dict[str, tuple[list[xr.Dataset], xr.Dataset | None]]:
    """What the figures show of ``runs`` and ``reference``, by the suffix of
    their files: the results themselves in 1D and 2D; of 3D results, the
    planes of cells nearest the middle of the box, X–Y (``_xy``) and X–Z
    (``_xz``, z drawn as y), or, where the output grid is one cell across
    two axes (a tube), the line along the third (drawn as x)."""
    first = runs[0]
    if "z" not in first.dims:
        return {"": (runs, reference)}
    long = [d for d in ("x", "y", "z") if first.sizes[d] > 1]
    if len(long) == 1:
        def cut(ds):
            line = ds.isel({d: 0 for d in ("x", "y", "z") if d != long[0]}, drop=True)
            return line.rename({long[0]: "x"}) if long[0] != "x" else line
        return {"": ([cut(ds) for ds in runs], None if reference is None else cut(reference))}

    def plane(ds, across, name):
        mid = float(first[across][first.sizes[across] // 2])
        cut = ds.sel({across: mid}, method="nearest", drop=True)
        cut.attrs = {**ds.attrs, "case": f"{ds.attrs['case']}, mid-plane {name} ({across} = {mid:.4g} m"
                                         f"{'; z drawn as y' if across == 'y' else ''})"}
        return cut.rename({"z": "y"}) if across == "y" else cut

    return {suffix: ([plane(ds, across, name) for ds in runs],
                     None if reference is None else plane(reference, across, name))
            for suffix, name, across in (("_xy", "X–Y", "z"), ("_xz", "X–Z", "y"))}


def report(runs: list[xr.Dataset], reference: xr.Dataset | None, names: list[str], folder: str | Path,
           versus: str = "the reference", timing: str | None = None) -> pd.DataFrame:
    """The table of :func:`table` (written by :func:`write_table`) and the
    figures of the runs into ``folder``: profiles (1D) or field maps with
    difference maps and numerical schlieren (2D; in 3D of the mid-planes,
    :func:`_views`), probe histories, wall
    force and impulse where the scene has them, and, against a reference,
    speed versus error and convergence of the L1 density error (``versus``
    names the reference in their titles). Where a method ran at three or
    more resolutions, the Richardson value and GCI of every quantity the
    scene measured (:func:`grid_convergence`) go to ``convergence.csv`` and
    ``convergence.json`` and the figure ``richardson.png``. ``timing`` says
    how the runs were timed (on the speed-against-error figure)."""
    folder = Path(folder)
    df = table(runs, reference, names)
    write_table(df, folder)
    first = runs[0]
    water = "eta" in first
    for view, (shown, ref) in _views(runs, reference).items():
        first_shown = shown[0]
        if "y" in first_shown.dims:
            for field in (f for f in ("rho", "p", "eta") if f in first_shown):
                plots.field_maps(shown, field, folder / f"{field}_maps{view}.png", reference=ref, names=names)
            if not water:
                plots.schlieren_maps(shown, folder / f"schlieren{view}.png", names=names)
        else:
            for field in (f for f in ("rho", "u", "v", "w", "p", "eta") if f in first_shown):
                plots.profiles(shown, field, folder / f"{field}{view}.png", reference=ref, names=names)
    for series in (s for s in ("p_probe", "eta_probe") if s in first):
        for probe in first.probe.values:
            # gauge records in seconds, blast probes in milliseconds
            plots.series(runs, series, folder / f"probe_{probe}.png", probe=str(probe), names=names,
                         reference=reference, **({} if water else {"scale": 1e3, "unit": "ms"}))
    for var in (v for v in ("wall_force", "wall_impulse") if v in first):
        plots.series(runs, var, folder / f"{var}.png", names=names, scale=1e3, unit="ms")
    convergence = grid_convergence(df, first.attrs.get("measured_quantities", "").split())
    if not convergence.empty:
        convergence.to_csv(folder / "convergence.csv", index=False)
        (folder / "convergence.json").write_text(
            json.dumps(convergence.to_dict(orient="records"), indent=2, default=float))
        if "f_ext" in convergence:
            plots.richardson(df, convergence, folder / "richardson.png",
                             f"{first.attrs['case']}: measured quantities to t = {float(first.time[-1]):.4g} s "
                             "against resolution")
    error, what = ("eta_L1", "surface elevation") if water else ("rho_L1", "density")
    if reference is not None and error in df and (df[error] > 0).any():
        title = f"{first.attrs['case']}: L1 {what} error against {versus} at t = {df['error_time'].max():.4g} s"
        plots.speed_versus_error(df, error, folder / "speed_versus_error.png", title if timing is None
                                 else f"{title}\n{timing}")
        plots.convergence(df, error, folder / "convergence.png", title)
    return df
