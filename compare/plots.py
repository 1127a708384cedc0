"""Figures of runs of one scene: profiles against a reference, probe
series overlaid, error against cost (speed versus error, with the Pareto
front) and error against resolution (convergence, with the observed
order). Every figure names the scene and time in its title, puts units on
its axes and a legend entry on every line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

from partmesh.compare.convergence import observed_order
from partmesh.compare.metrics import measured_unit, schlieren
from partmesh.compare.pareto import pareto_front


def _subplots(rows: int = 1, columns: int = 1, figsize=None, layout=None, **kwargs):
    """A figure and its axes, drawn on a :class:`~matplotlib.figure.Figure`
    of its own: no pyplot state and no backend is chosen or changed, so the
    figures of a report do not touch an interactive session's."""
    fig = Figure(figsize=figsize, layout=layout)
    return fig, fig.subplots(rows, columns, **kwargs)


def _label(ds: xr.Dataset, name: str | None = None) -> str:
    if name:
        return f"{name} ({ds.attrs['n_elements']} elements)"
    return f"{ds.attrs['method']} (dx = {ds.attrs['dx']:.3g} m, {ds.attrs['n_elements']} elements)"


def _reference_name(reference: xr.Dataset) -> str:
    return "exact" if reference.attrs.get("method") == "exact" else "reference"


def _axis_label(var: xr.DataArray) -> str:
    """``long name [units]``, the long name up to its first comma (an axis has no room for the rest)."""
    return f"{var.attrs.get('long_name', var.name).split(',')[0]} [{var.attrs.get('units', '')}]"


#: a profile whose total variation exceeds this many times the smoothest one's is drawn as noise
NOISY = 2.0
#: the cells of the running mean drawn over a noisy profile
WINDOW = 9


def _variation(profile: xr.DataArray) -> float:
    """The total variation Σ|Δv| of a profile (NaN gaps left out)."""
    return float(np.nansum(np.abs(np.diff(profile.values))))


def profiles(runs, field: str, path, reference: xr.Dataset | None = None, names=None, time=None) -> Path:
    """1D profiles of ``field`` at ``time`` (default: the last output time)
    for every run, with the reference drawn as a black line on top. A
    noisy run (total variation beyond :data:`NOISY` times the smoothest
    profile's) is drawn as a light band of its raw values under its
    :data:`WINDOW`-cell running mean."""
    names = names or [None] * len(runs)
    t = float(runs[0].time[-1]) if time is None else time
    fig, ax = _subplots(figsize=(7, 4.2))
    if reference is not None:
        ref = reference[field].sel(time=t, method="nearest")
        # on top of the runs: a particle method's scatter would hide it
        ax.plot(reference.x, ref, "k-", lw=1.4, zorder=10, label=_reference_name(reference))
    values = [ds[field].sel(time=t, method="nearest") for ds in runs]
    # a noisy profile (a particle method's scatter) is drawn as a light band of its raw values under its
    # windowed mean, and the roughest first, so that it hides neither the smooth runs nor the reference;
    # the legend keeps the runs' order
    roughness = [_variation(v) for v in values]
    smoothest = min(roughness + ([_variation(ref)] if reference is not None else []))
    lines = {}
    for k in np.argsort(roughness)[::-1]:
        label = _label(runs[k], names[k])
        if roughness[k] > NOISY * smoothest:
            ax.plot(runs[k].x, values[k], "-", lw=0.6, alpha=0.3, color=f"C{k}")
            mean = values[k].rolling(x=WINDOW, center=True, min_periods=WINDOW // 2 + 1).mean()
            lines[k] = ax.plot(runs[k].x, mean, "-", lw=1.6, color=f"C{k}",
                               label=f"{label}, {WINDOW}-cell mean (light: raw)")[0]
        else:
            lines[k] = ax.plot(runs[k].x, values[k], ".-", ms=3, lw=0.8, color=f"C{k}", label=label)[0]
    var = runs[0][field]
    ax.set_xlabel(_axis_label(runs[0].x))
    ax.set_ylabel(_axis_label(var))
    ax.set_title(f"{runs[0].attrs['case']}: {var.attrs.get('long_name', field)} at t = {t:.4g} s")
    handles = ax.get_lines()[:1] if reference is not None else []
    ax.legend(handles=handles + [lines[k] for k in range(len(runs))], fontsize=8)
    ax.grid(alpha=0.3)
    return _save(fig, path)


def series(runs, var: str, path, probe: str | None = None, names=None, scale: float = 1.0, unit: str | None = None,
           reference: xr.Dataset | None = None, title: str | None = None) -> Path:
    """Time series ``var`` (``p_probe`` or ``eta_probe`` at ``probe``,
    ``wall_force``, ``wall_impulse``) of every run, overlaid, with the
    reference's as a black line where it has that series; ``scale``
    multiplies the time axis (e.g. 1e3 for ms, named by ``unit``);
    ``title`` replaces the scene's name in the title. A noisy series (total
    variation beyond :data:`NOISY` times the smoothest run's) is drawn as a
    light band under its running mean over a sixtieth of the record (at
    least :data:`WINDOW` samples)."""
    names = names or [None] * len(runs)
    fig, ax = _subplots(figsize=(7, 4.2))
    if reference is not None and var in reference:
        ref = reference[var].sel(probe=probe) if probe is not None else reference[var]
        ax.plot(reference.t_probe * scale, ref, "k-", lw=1.4, zorder=10, label=_reference_name(reference))
    handles = ax.get_lines()[:1]
    values = [ds[var].sel(probe=probe) if probe is not None else ds[var] for ds in runs]
    roughness = [_variation(y) for y in values]
    smoothest = min(roughness)
    lines = {}
    # as in :func:`profiles`: a noisy series (DSMC's wall force) is a light band under its running mean,
    # the roughest drawn first; the legend keeps the runs' order
    for k in np.argsort(roughness)[::-1]:
        ds, y, label = runs[k], values[k], _label(runs[k], names[k])
        # beyond the ten colours of the cycle, the same colours dashed, then dotted
        style = dict(color=f"C{k % 10}", ls=("-", "--", ":", "-.")[k // 10 % 4])
        if roughness[k] > NOISY * smoothest:
            window = max(WINDOW, y.size // 60)
            ax.plot(ds.t_probe * scale, y, lw=0.5, alpha=0.3, **style)
            y = y.rolling(t_probe=window, center=True, min_periods=window // 2 + 1).mean()
            label = f"{label}, {window}-sample mean (light: raw)"
        lines[k] = ax.plot(ds.t_probe * scale, y, lw=1.0, label=label, **style)[0]
    first = runs[0][var]
    ax.set_xlabel(f"time [{unit or 's'}]")
    ax.set_ylabel(_axis_label(first))
    where = f" {probe!r}" if probe is not None else ""
    what = first.attrs.get("long_name", var).split(",")[0]
    ax.set_title(f"{title or runs[0].attrs['case']}: {what}{where}", fontsize=10)
    if len(runs) > 6:  # (beside the axes: inside, a long legend hides the lines)
        fig.set_size_inches(10.5, 4.2)
        ax.legend(handles=handles + [lines[k] for k in range(len(runs))], fontsize=7, loc="upper left",
                  bbox_to_anchor=(1.01, 1.0))
    else:
        ax.legend(handles=handles + [lines[k] for k in range(len(runs))], fontsize=8)
    ax.grid(alpha=0.3)
    return _save(fig, path)


def speed_versus_error(df, error: str, path, title: str, ylabel: str | None = None) -> Path:
    """``error`` (a column of a :func:`partmesh.compare.report.table`) against wall
    time, log–log, one line per method through its resolutions, the Pareto
    front (no run both faster and more accurate) drawn and its runs ringed;
    ``ylabel`` names the error (default: from the column, 'L1 error of rho')."""
    fig, ax = _subplots(figsize=(7, 4.6))
    rows = df[(df[error] > 0) & np.isfinite(df["wall_seconds"])]  # (a reference run's own error, 0, has no place)
    for method, group in rows.groupby("method", sort=False):
        group = group.sort_values("wall_seconds")
        ax.plot(group["wall_seconds"], group[error], "o-", label=method)
    front = rows[pareto_front(rows["wall_seconds"], rows[error])].sort_values("wall_seconds")
    ax.step(front["wall_seconds"], front[error], "k--", where="post", lw=0.8, label="Pareto front")
    ax.plot(front["wall_seconds"], front[error], "o", ms=11, mfc="none", mec="k")
    return _save_log_log(fig, ax, "wall time [s]", error, title, path, ylabel)


def trends(df, x: str, quantities, path, title: str, xlabel: str, labels=None, scales=None) -> Path:
    """``quantities`` (columns of ``df``) against the column ``x``, one
    panel each, one line per ``method`` and ``shape`` (methods by colour,
    shapes by marker and line style); ``labels`` and ``scales`` name and
    scale each quantity (e.g. N/m as kN/m)."""
    labels, scales = labels or {}, scales or {}
    columns = min(2, len(quantities))
    rows = -(-len(quantities) // columns)
    fig, axes = _subplots(rows, columns, figsize=(4.6 * columns, 3.4 * rows), squeeze=False)
    colours = {m: f"C{k}" for k, m in enumerate(dict.fromkeys(df["method"]))}
    styles = {s: st for s, st in zip(dict.fromkeys(df["shape"]), (("o", "-"), ("s", "--"), ("^", ":"), ("D", "-.")))}
    for ax in axes.flat[len(quantities):]:
        ax.set_visible(False)
    for ax, q in zip(axes.flat, quantities):
        for (method, shape), group in df.groupby(["method", "shape"], sort=False):
            group = group.sort_values(x)
            marker, line = styles[shape]
            ax.plot(group[x], group[q] * scales.get(q, 1.0), marker=marker, ls=line, color=colours[method],
                    label=f"{method}, {shape}")
        ax.set_xticks(sorted(df[x].unique()))
        ax.set_xlabel(xlabel)
        ax.set_ylabel(labels.get(q, q.replace("_", " ")))
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=8)
    fig.suptitle(title)
    return _save(fig, path)


def convergence(df, error: str, path, title: str) -> Path:
    """``error`` against ``dx``, log–log, one line per method, its observed
    order (least-squares slope) in the legend where it has ≥ 2 levels."""
    fig, ax = _subplots(figsize=(7, 4.6))
    rows = df[df[error] > 0]
    for method, group in rows.groupby("method", sort=False):
        group = group.sort_values("dx")
        label = method
        if group["dx"].nunique() >= 2:
            label += f" (order {observed_order(group['dx'], group[error]):.2f})"
        ax.plot(group["dx"], group[error], "o-", label=label)
    return _save_log_log(fig, ax, "cell size or particle spacing dx [m]", error, title, path)


def richardson(df, convergence, path, title: str) -> Path:
    """One panel per measured quantity of ``convergence`` (a
    :func:`partmesh.compare.report.grid_convergence` table): the quantity against
    dx for every run of each method in ``df``, its Richardson value as a
    dashed line and the finest level's GCI as an error bar, both in the
    legend."""
    quantities = list(dict.fromkeys(convergence["quantity"]))
    cols = min(3, len(quantities))
    rows_n = -(-len(quantities) // cols)
    fig, axes = _subplots(rows_n, cols, figsize=(4.4 * cols, 3.4 * rows_n + 0.4), squeeze=False)
    for ax, quantity in zip(axes.flat, quantities):
        for k, (_, row) in enumerate(convergence[convergence["quantity"] == quantity].iterrows()):
            colour = f"C{k}"
            runs = df[df["method"] == row["method"]].sort_values("dx")
            if isinstance(row.get("note"), str):
                label = f"{row['method']}: not converging"
            else:
                ax.axhline(row["f_ext"], color=colour, ls="--", lw=0.9)
                ax.errorbar(row["dx1"], row["f1"], yerr=row["gci_fine"] * abs(row["f1"]), color=colour, capsize=4)
                label = (f"{row['method']}: order {row['p']:.2f}, Richardson {row['f_ext']:.5g},\n"
                         f"GCI {100 * row['gci_fine']:.2g} %")
            ax.plot(runs["dx"], runs[quantity], "o-", color=colour, ms=4, label=label)
        unit = measured_unit(quantity)
        _plain_log_axis(ax.xaxis, ax.set_xscale)
        ax.set_xticks(sorted(set(df["dx"].dropna())))  # every level labelled (a ladder may span less than a decade)
        ax.set_xlabel("cell size or particle spacing dx [m]", fontsize=8)
        ax.set_ylabel(f"{quantity} [{unit}]" if unit else quantity, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3, which="both")
    for ax in list(axes.flat)[len(quantities):]:
        ax.axis("off")
    fig.suptitle(f"{title}; Richardson value dashed, GCI of the finest level as error bar", fontsize=10)
    return _save(fig, path)


def field_maps(runs, field: str, path, reference: xr.Dataset | None = None, names=None, time=None,
               columns: int | None = None) -> Path:
    """2D maps of ``field`` at ``time`` (default: the last output time), one
    panel per run on one colour scale (the reference first, if given), and
    under them each run minus the reference on one symmetric scale. Without
    a reference the panels stand in ``columns`` columns (default: one row)."""
    names = names or [None] * len(runs)
    t = float(runs[0].time[-1]) if time is None else time
    maps = [ds[field].sel(time=t, method="nearest") for ds in runs]
    ref = reference[field].sel(time=t, method="nearest") if reference is not None else None
    shown = ([ref] if ref is not None else []) + maps
    ref_name = _reference_name(reference) if reference is not None else None
    titles = ([ref_name] if ref is not None else []) + [_label(ds, n) for ds, n in zip(runs, names)]
    lo = min(float(np.nanmin(m)) for m in shown)
    hi = max(float(np.nanmax(m)) for m in shown)
    columns = len(shown) if ref is not None or columns is None else columns
    fig, axes = _map_grid(runs[0], len(shown) * (2 if ref is not None else 1), columns)
    var = runs[0][field]
    unit = var.attrs.get("units", "")
    panels = axes.flat[:len(shown)]
    for ax, m, title in zip(panels, shown, titles):
        image = ax.pcolormesh(m.x, m.y, m, vmin=lo, vmax=hi, shading="nearest", cmap="viridis")
        ax.set_title(title, fontsize=8)
    fig.colorbar(image, ax=list(panels), label=f"{field} [{unit}]", shrink=0.9)
    if ref is not None:
        differences = [m - ref for m in maps]
        limit = max(float(np.nanmax(np.abs(d))) for d in differences) or 1.0
        axes[1, 0].axis("off")
        for ax, d, title in zip(axes[1, 1:], differences, titles[1:]):
            image = ax.pcolormesh(d.x, d.y, d, vmin=-limit, vmax=limit, shading="nearest", cmap="RdBu_r")
            ax.set_title(f"{title}\nminus {ref_name}", fontsize=8)
        fig.colorbar(image, ax=list(axes[1]), label=f"difference in {field} [{unit}]", shrink=0.9)
    _map_axes(axes)
    if ref is not None:
        axes[1, 1].set_ylabel("y [m]", fontsize=8)
    fig.suptitle(f"{runs[0].attrs['case']}: {var.attrs.get('long_name', field)} at t = {t:.4g} s", fontsize=10)
    return _save(fig, path, tight=False)


def schlieren_maps(runs, path, names=None, time=None, k: float = 8.0, columns: int | None = None) -> Path:
    """Numerical schlieren (:func:`partmesh.compare.metrics.schlieren`) of every run's
    density at ``time`` (default: the last output time), in ``columns``
    columns (default: side by side in one row), each panel sized to the
    domain's aspect ratio."""
    names = names or [None] * len(runs)
    t = float(runs[0].time[-1]) if time is None else time
    fig, axes = _map_grid(runs[0], len(runs), columns or len(runs))
    for ax, ds, name in zip(axes.flat, runs, names):
        shade = schlieren(ds["rho"].sel(time=t, method="nearest"), k=k)
        ax.pcolormesh(shade.x, shade.y, shade, vmin=0.0, vmax=1.0, shading="nearest", cmap="gray")
        ax.set_title(_label(ds, name), fontsize=8)
    _map_axes(axes)
    fig.suptitle(f"{runs[0].attrs['case']}: numerical schlieren exp(-{k:g} |grad rho| / max) at t = {t:.4g} s",
                 fontsize=10)
    return _save(fig, path, tight=False)


def _map_grid(ds: xr.Dataset, panels: int, columns: int):
    """``(fig, axes)``: ``panels`` map panels of ``ds``'s domain in
    ``columns`` columns, each sized to the domain's aspect ratio (a lone
    column: a wide channel across the page); panels past ``panels`` hidden."""
    rows = -(-panels // columns)
    x, y = ds.x.values, ds.y.values
    width = 3.2 if columns > 1 else 9.0
    aspect = float(np.ptp(y) / np.ptp(x)) if x.size > 1 and y.size > 1 else 1.0
    height = min(max(width * aspect, 1.0), 3.2)
    fig, axes = _subplots(rows, columns, figsize=(width * columns + 1.2, (height + 0.5) * rows + 0.4),
                             squeeze=False, layout="constrained")
    for ax in axes.flat[panels:]:
        ax.axis("off")
    return fig, axes


def _map_axes(axes) -> None:
    """Equal-aspect map panels, x labelled on every panel, y on the first
    column."""
    for (row, col), ax in np.ndenumerate(axes):
        ax.set_aspect("equal")
        ax.locator_params(nbins=5)
        ax.set_xlabel("x [m]", fontsize=8)
        if col == 0:
            ax.set_ylabel("y [m]", fontsize=8)
        ax.tick_params(labelsize=7)


def _save_log_log(fig, ax, xlabel: str, error: str, title: str, path, ylabel: str | None = None) -> Path:
    """Finish an error plot: log–log axes labelled with plain numbers at 1,
    2 and 5 times the powers of ten, the error column ('rho_L1') named as
    'L1 error of rho', title, legend, grid; save it."""
    for axis, scale in ((ax.xaxis, ax.set_xscale), (ax.yaxis, ax.set_yscale)):
        _plain_log_axis(axis, scale)
    field, _, norm = error.rpartition("_")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel or f"{norm} error of {field}")
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    return _save(fig, path)


def _plain_log_axis(axis, set_scale) -> None:
    """A log axis with plain numbers at 1, 2 and 5 times the powers of ten."""
    set_scale("log")
    axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
    axis.set_minor_formatter(NullFormatter())


def _save(fig, path, tight: bool = True) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if tight:
        fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path
