"""Field errors: the discrete L1, L2 and L∞ norms of the difference of two
fields on one grid, and of every field of a run against a reference."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import reduce

import numpy as np
import xarray as xr

from partmesh.compare.checks import number
from partmesh.compare.metrics.samples import coordinate, dataarray, pair

#: the norms :func:`field_error` knows.
NORMS = ("L1", "L2", "Linf")


_COORD_ATOL = 1e-12  # two grids are the same when their coordinates agree to this (× max(1, |c|))


def _norm_name(norm) -> str:
    names = {n.lower(): n for n in NORMS}
    key = str(norm).lower()
    if key not in names:
        raise ValueError(f"norm must be one of {', '.join(NORMS)}, got {norm!r}.")
    return names[key]


def _cell_widths(c: np.ndarray) -> np.ndarray:
    """Widths of the cells around centres ``c``: edges halfway between centres,
    the outer edges mirrored (uniform grids give the constant spacing)."""
    if c.size == 1:
        return np.ones(1)
    mid = 0.5 * (c[1:] + c[:-1])
    edges = np.concatenate(([c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]))
    return np.abs(np.diff(edges))


def field_error(a: xr.DataArray, b: xr.DataArray, norm: str = "L1", region: Mapping | None = None, mask=None) -> float:
    """Cell-size-weighted error norm between two fields on the same grid.

    With d = a − b and the cell sizes ΔV_i (Δx in 1D, Δx Δy in 2D, Δx Δy Δz in 3D; for a
    non-uniform coordinate the cell edges lie halfway between centres) over
    the compared cells C:

        L1   = Σ_C |d_i| ΔV_i / Σ_C ΔV_i          (mean absolute error)
        L2   = ( Σ_C d_i² ΔV_i / Σ_C ΔV_i )^(1/2)  (root mean square error)
        Linf = max_C |d_i|

    the discrete, volume-normalised Lebesgue norms used for the Sod and Sedov
    error tables (e.g. Toro 2009, *Riemann Solvers and Numerical Methods for
    Fluid Dynamics*, §6.4). C is every cell where both a and b are finite
    (NaN marks solids and cells without support), inside ``region`` and
    where ``mask`` is true.

    Parameters
    ----------
    a, b : DataArray on ``(x,)``, ``(y, x)`` or ``(z, y, x)`` (any 1 to 3 dims, same on both)
        b may list its dims in another order; it is transposed to a's.
    norm : "L1", "L2" or "Linf" (case-insensitive).
    region : dict, optional
        ``{"x": (x0, x1), "y": (y0, y1)}``: compare only cells whose centres
        lie in the closed intervals (any subset of a's dims).
    mask : bool array or DataArray of a's shape, optional
        True (non-zero) where cells are compared. To compare away from
        solids use ``mask=(ds.solid == 0)``; fields are NaN inside solids
        anyway.

    Raises
    ------
    ValueError
        for an unknown norm, a/b with other than 1 to 3 dims or with
        different dims, coordinates that differ by more than 1e-12 (relative
        to max(1, |coordinate|); the message names the coordinate), a bad
        region or mask, or no cell left to compare.
    """
    a = dataarray("a", a)
    b = dataarray("b", b)
    norm = _norm_name(norm)
    if a.ndim not in (1, 2, 3):
        raise ValueError(f"a must be a 1D (x), 2D (y, x) or 3D (z, y, x) field (select a time first), "
                         f"got dims {a.dims}.")
    if set(a.dims) != set(b.dims):
        raise ValueError(f"b must have the same dims as a {a.dims}, got {b.dims}.")
    b = b.transpose(*a.dims)
    for d in a.dims:
        ca, cb = coordinate(a, d), coordinate(b, d)
        if ca.shape != cb.shape:
            raise ValueError(f"a and b lie on different grids: coordinate {d!r} has {ca.size} vs {cb.size} points.")
        tol = _COORD_ATOL * max(1.0, float(np.max(np.abs(ca))) if ca.size else 1.0)
        if not np.all(np.abs(ca - cb) <= tol):
            raise ValueError(
                f"a and b lie on different grids: coordinate {d!r} differs by up to "
                f"{float(np.max(np.abs(ca - cb))):.3g} (allowed 1e-12)."
            )
    av = np.asarray(a.values, dtype=float)
    bv = np.asarray(b.values, dtype=float)
    keep = np.isfinite(av) & np.isfinite(bv)

    coords = {d: coordinate(a, d) for d in a.dims}
    if region is not None:
        if not isinstance(region, Mapping):
            raise ValueError("region must be a dict like {'x': (x0, x1), 'y': (y0, y1)}.")
        for d, bounds in region.items():
            if d not in a.dims:
                raise ValueError(f"region names dim {d!r}; allowed: {', '.join(a.dims)}.")
            lo, hi = pair(f"region[{d!r}]", bounds, "(lo, hi)")
            if not lo <= hi:
                raise ValueError(f"region[{d!r}] = ({lo}, {hi}) must have lo <= hi.")
            inside = (coords[d] >= lo) & (coords[d] <= hi)
            shape = [1] * a.ndim
            shape[a.dims.index(d)] = -1
            keep &= inside.reshape(shape)
    if mask is not None:
        if isinstance(mask, xr.DataArray):
            if set(mask.dims) != set(a.dims):
                raise ValueError(f"mask must have the dims of a {a.dims}, got {mask.dims}.")
            m = np.asarray(mask.transpose(*a.dims).values)
        else:
            m = np.asarray(mask)
        if m.shape != av.shape:
            raise ValueError(f"mask must have the shape of a {av.shape}, got {m.shape}.")
        keep &= np.where(np.isfinite(m.astype(float)), m.astype(float), 0.0) != 0.0
    if not keep.any():
        raise ValueError("no cell is left to compare: a and b are NaN everywhere inside region and mask.")

    diff = np.abs(av - bv)[keep]
    if norm == "Linf":
        return float(diff.max())
    widths = [_cell_widths(coords[d]) for d in a.dims]
    vol = reduce(np.multiply.outer, widths)
    w = vol[keep]
    if norm == "L1":
        return float(np.sum(diff * w) / np.sum(w))
    return float(np.sqrt(np.sum(diff * diff * w) / np.sum(w)))


def _common_times(t_run: np.ndarray, t_ref: np.ndarray) -> np.ndarray:
    scale = max(1e-300, float(np.max(np.abs(np.concatenate((t_run, t_ref))))))
    close = np.isclose(t_run[:, None], t_ref[None, :], rtol=0.0, atol=1e-9 * scale)
    return t_run[close.any(axis=1)]


def errors(
    run: xr.Dataset,
    reference: xr.Dataset,
    fields: Sequence[str] | None = None,
    time: float | None = None,
    norms: Sequence[str] = NORMS,
    region: Mapping | None = None,
    mask=None,
) -> dict[tuple[str, str], float]:
    """Field errors of ``run`` against ``reference`` at one output time.

    Returns ``{(field, norm): value}`` with each value from
    :func:`field_error` (L1 = Σ|a−b|ΔV/ΣΔV, L2 = root-mean-square,
    Linf = max, NaN cells left out) for the field at ``time``.

    Parameters
    ----------
    run, reference : schema Datasets on the same output grid.
    fields : names, optional
        Default: every variable with a ``time`` dim and the grid's spatial
        dims present in both (``rho``, ``u``, ``p``, ...).
    time : float, optional
        An output time present in both (to 1e-9 of the largest time);
        default: the last common output time.
    norms : subset of ("L1", "L2", "Linf").
    region, mask : passed to :func:`field_error`.

    Raises
    ------
    ValueError
        when an argument is not a Dataset, a requested field is missing in
        either, no field or time is shared, or ``time`` is not an output
        time of both.
    """
    if not isinstance(run, xr.Dataset):
        raise ValueError(f"run must be an xarray.Dataset, got {type(run).__name__}.")
    if not isinstance(reference, xr.Dataset):
        raise ValueError(f"reference must be an xarray.Dataset, got {type(reference).__name__}.")
    norms = [_norm_name(n) for n in norms]
    if not norms:
        raise ValueError("norms must name at least one of L1, L2, Linf.")
    for name, ds in (("run", run), ("reference", reference)):
        if "time" not in ds.coords:
            raise ValueError(f"{name} has no 'time' coordinate, so it holds no fields to compare.")

    def _is_field(ds, name):
        return name in ds.data_vars and "time" in ds[name].dims and ds[name].ndim in (2, 3)

    if fields is None:
        fields = [n for n in run.data_vars if _is_field(run, n) and _is_field(reference, n)]
        if not fields:
            raise ValueError("run and reference share no field on (time, [y,] x); pass fields explicitly.")
    else:
        fields = [fields] if isinstance(fields, str) else list(fields)
        for n in fields:
            for name, ds in (("run", run), ("reference", reference)):
                if not _is_field(ds, n):
                    raise ValueError(f"fields names {n!r}, which {name} does not hold as a (time, [y,] x) field.")

    t_run = np.asarray(run["time"].values, dtype=float)
    t_ref = np.asarray(reference["time"].values, dtype=float)
    common = _common_times(t_run, t_ref)
    if time is None:
        if common.size == 0:
            raise ValueError("run and reference share no output time; pass time explicitly.")
        time = float(common.max())
    else:
        time = number("time", time)
        if not np.any(np.isclose(common, time, rtol=0.0, atol=1e-9 * max(1e-300, np.max(np.abs(common), initial=abs(time))))):
            allowed = ", ".join(f"{t:g}" for t in common) or "none"
            raise ValueError(f"time={time:g} is not an output time of both run and reference (common: {allowed}).")

    out: dict[tuple[str, str], float] = {}
    for n in fields:  # loop over a handful of field names, not cells
        a = run[n].sel(time=time, method="nearest")
        b = reference[n].sel(time=time, method="nearest")
        for nm in norms:
            out[(n, nm)] = field_error(a, b, norm=nm, region=region, mask=mask)
    return out
