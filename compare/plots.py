"""Figures of runs of one scene: profiles against a reference and probe
series overlaid. Every figure names the scene and time in its title, puts
units on its axes and a legend entry on every line."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import xarray as xr  # noqa: E402


def _label(ds: xr.Dataset, name: str | None = None) -> str:
    if name:
        return f"{name} ({ds.attrs['n_elements']} elements)"
    return f"{ds.attrs['method']} (dx = {ds.attrs['dx']:.3g} m, {ds.attrs['n_elements']} elements)"


def _axis_label(var: xr.DataArray) -> str:
    return f"{var.attrs.get('long_name', var.name)} [{var.attrs.get('units', '')}]"


def profiles(runs, field: str, path, reference: xr.Dataset | None = None, names=None, time=None) -> Path:
    """1D profiles of ``field`` at ``time`` (default: the last output time)
    for every run, with the reference drawn as a black line."""
    names = names or [None] * len(runs)
    t = float(runs[0].time[-1]) if time is None else time
    fig, ax = plt.subplots(figsize=(7, 4.2))
    if reference is not None:
        ref = reference[field].sel(time=t, method="nearest")
        ax.plot(reference.x, ref, "k-", lw=1.2, label="exact" if reference.attrs["method"] == "exact" else "reference")
    for ds, name in zip(runs, names):
        ax.plot(ds.x, ds[field].sel(time=t, method="nearest"), ".-", ms=3, lw=0.8, label=_label(ds, name))
    var = runs[0][field]
    ax.set_xlabel(_axis_label(runs[0].x))
    ax.set_ylabel(_axis_label(var))
    ax.set_title(f"{runs[0].attrs['case']}: {var.attrs.get('long_name', field)} at t = {t:.4g} s")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return _save(fig, path)


def series(runs, var: str, path, probe: str | None = None, names=None, scale: float = 1.0, unit: str | None = None) -> Path:
    """Time series ``var`` (``p_probe`` at ``probe``, ``wall_force``,
    ``wall_impulse``) of every run, overlaid; ``scale`` multiplies the time
    axis (e.g. 1e3 for ms, named by ``unit``)."""
    names = names or [None] * len(runs)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for ds, name in zip(runs, names):
        y = ds[var].sel(probe=probe) if probe is not None else ds[var]
        ax.plot(ds.t_probe * scale, y, lw=1.0, label=_label(ds, name))
    first = runs[0][var]
    ax.set_xlabel(f"time [{unit or 's'}]")
    ax.set_ylabel(_axis_label(first))
    where = f" {probe!r}" if probe is not None else ""
    ax.set_title(f"{runs[0].attrs['case']}: {first.attrs.get('long_name', var)}{where}", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return _save(fig, path)


def _save(fig, path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path
