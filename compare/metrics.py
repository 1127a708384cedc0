"""Scalar measures of a result: field errors, shock positions, probe-series
metrics, oblique-shock angles and conservation drift (SPEC §5).

Every function works on the schema's objects (:mod:`partmesh.compare.schema`):
fields are :class:`xarray.DataArray` on ``([y,] x)`` (select a ``time``
first), probe series are 1D DataArrays on ``t_probe`` (select a ``probe``
first, e.g. ``ds.p_probe.sel(probe="w")``). NaN marks cells inside solids or
without support and is left out everywhere.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
import xarray as xr

from partmesh.compare.checks import number

__all__ = [
    "NORMS",
    "field_error",
    "errors",
    "shock_position",
    "shock_radius",
    "arrival_time",
    "peak",
    "positive_phase",
    "plateau",
    "oblique_shock_angle",
    "conservation_drift",
]

#: the norms :func:`field_error` knows.
NORMS = ("L1", "L2", "Linf")

#: units of the scalar quantities scenes measure with this module (``partmesh.dispatch`` attaches them to a result)
MEASURED_UNITS = {
    "wall_peak_pressure_raw": "Pa", "wall_peak_pressure_fitted": "Pa", "wall_arrival_time": "s",
    "wall_impulse_final": "N s m-1", "wall_force_peak_raw": "N m-1",
    "wall_force_peak_fitted": "N m-1", "reflection_coefficient": "1",
    "shock_angle_deg": "degree", "shock_radius": "m", "first_crest_height": "m", "first_crest_time": "s",
    "first_crest_arrival": "s",
}


def measured_unit(name: str) -> str | None:
    """The unit of the measured quantity ``name``: from :data:`MEASURED_UNITS`,
    by its name or, for per-probe quantities (``first_crest_height_x4.57``),
    by the name they extend."""
    if name in MEASURED_UNITS:
        return MEASURED_UNITS[name]
    stems = [key for key in MEASURED_UNITS if name.startswith(key + "_")]
    return MEASURED_UNITS[max(stems, key=len)] if stems else None

_COORD_ATOL = 1e-12  # two grids are the same when their coordinates agree to this (× max(1, |c|))


# ---------------------------------------------------------------------------
# helpers


def _norm_name(norm) -> str:
    names = {n.lower(): n for n in NORMS}
    key = str(norm).lower()
    if key not in names:
        raise ValueError(f"norm must be one of {', '.join(NORMS)}, got {norm!r}.")
    return names[key]


def _require_dataarray(name: str, a) -> xr.DataArray:
    if not isinstance(a, xr.DataArray):
        raise ValueError(f"{name} must be an xarray.DataArray, got {type(a).__name__}.")
    return a


def _coord(a: xr.DataArray, dim: str) -> np.ndarray:
    return np.asarray(a[dim].values, dtype=float) if dim in a.coords else np.arange(a.sizes[dim], dtype=float)


def _cell_widths(c: np.ndarray) -> np.ndarray:
    """Widths of the cells around centres ``c``: edges halfway between centres,
    the outer edges mirrored (uniform grids give the constant spacing)."""
    if c.size == 1:
        return np.ones(1)
    mid = 0.5 * (c[1:] + c[:-1])
    edges = np.concatenate(([c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]))
    return np.abs(np.diff(edges))


def _series(name: str, series) -> tuple[np.ndarray, np.ndarray]:
    """(t, v) of a 1D time series DataArray, NaN samples dropped, sorted in t."""
    s = _require_dataarray(name, series)
    if s.ndim != 1:
        raise ValueError(
            f"{name} must be a 1D time series (select one probe first), got dims {s.dims}."
        )
    t = _coord(s, s.dims[0])
    v = np.asarray(s.values, dtype=float)
    ok = np.isfinite(t) & np.isfinite(v)
    t, v = t[ok], v[ok]
    if t.size < 2:
        raise ValueError(f"{name} must hold at least 2 finite samples, got {t.size}.")
    order = np.argsort(t, kind="stable")
    t, v = t[order], v[order]
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"{name} has repeated sample times; its time coordinate must be strictly increasing.")
    return t, v


def _pair(name: str, v, what: str = "(a, b)") -> tuple[float, float]:
    """Two finite numbers, or a ValueError naming ``name``."""
    try:
        items = list(v)
    except TypeError:
        items = None
    if items is None or len(items) != 2:
        raise ValueError(f"{name} must be a pair {what} of numbers, got {v!r}.")
    return number(name, items[0]), number(name, items[1])


def _crossings(x: np.ndarray, v: np.ndarray, level: float) -> np.ndarray:
    """All positions where the piecewise-linear interpolant of (x, v) equals
    ``level`` (sample points equal to level count once), sorted."""
    s = v - level
    on = s == 0.0
    between = (s[:-1] * s[1:] < 0.0)
    i = np.nonzero(between)[0]
    xc = x[i] + (level - v[i]) * (x[i + 1] - x[i]) / (v[i + 1] - v[i])
    return np.sort(np.concatenate((xc, x[on])))


def _vertex(x: np.ndarray, g: np.ndarray, i: int) -> tuple[float, float]:
    """``(x, g)`` at the vertex of the parabola through samples i − 1, i and
    i + 1 (a local maximum), kept within [x_{i−1}, x_{i+1}]; the sample itself
    at an end of the record or on a flat top."""
    if i == 0 or i == g.size - 1:
        return float(x[i]), float(g[i])
    x0, x1, x2 = x[i - 1], x[i], x[i + 1]
    g0, g1, g2 = g[i - 1], g[i], g[i + 1]
    den = (x0 - x1) * (x0 - x2) * (x1 - x2)
    a = (x2 * (g1 - g0) + x1 * (g0 - g2) + x0 * (g2 - g1)) / den
    b = (x2 * x2 * (g0 - g1) + x1 * x1 * (g2 - g0) + x0 * x0 * (g1 - g2)) / den
    if not a < 0.0:  # flat top: no interior vertex
        return float(x1), float(g1)
    xv = float(np.clip(-b / (2.0 * a), x0, x2))
    return xv, float(g1 + (xv - x1) * (b + a * (xv + x1)))


def _parabolic_peak(x: np.ndarray, g: np.ndarray) -> float:
    """Vertex of the parabola through the maximum of g and its two neighbours."""
    return _vertex(x, g, int(np.argmax(g)))[0]


# ---------------------------------------------------------------------------
# field errors


def field_error(a: xr.DataArray, b: xr.DataArray, norm: str = "L1", region: Mapping | None = None, mask=None) -> float:
    """Cell-size-weighted error norm between two fields on the same grid.

    With d = a − b and the cell sizes ΔV_i (Δx in 1D, Δx Δy in 2D; for a
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
    a, b : DataArray on ``(x,)`` or ``(y, x)`` (any 1 or 2 dims, same on both)
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
        for an unknown norm, a/b with other than 1 or 2 dims or with
        different dims, coordinates that differ by more than 1e-12 (relative
        to max(1, |coordinate|); the message names the coordinate), a bad
        region or mask, or no cell left to compare.
    """
    a = _require_dataarray("a", a)
    b = _require_dataarray("b", b)
    norm = _norm_name(norm)
    if a.ndim not in (1, 2):
        raise ValueError(f"a must be a 1D (x) or 2D (y, x) field (select a time first), got dims {a.dims}.")
    if set(a.dims) != set(b.dims):
        raise ValueError(f"b must have the same dims as a {a.dims}, got {b.dims}.")
    b = b.transpose(*a.dims)
    for d in a.dims:
        ca, cb = _coord(a, d), _coord(b, d)
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

    coords = {d: _coord(a, d) for d in a.dims}
    if region is not None:
        if not isinstance(region, Mapping):
            raise ValueError("region must be a dict like {'x': (x0, x1), 'y': (y0, y1)}.")
        for d, bounds in region.items():
            if d not in a.dims:
                raise ValueError(f"region names dim {d!r}; allowed: {', '.join(a.dims)}.")
            lo, hi = _pair(f"region[{d!r}]", bounds, "(lo, hi)")
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
    vol = widths[0] if a.ndim == 1 else np.outer(widths[0], widths[1])
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


# ---------------------------------------------------------------------------
# shocks


def _profile(name: str, profile) -> tuple[np.ndarray, np.ndarray]:
    p = _require_dataarray(name, profile)
    if p.ndim != 1:
        raise ValueError(f"{name} must be a 1D profile along x or a radius, got dims {p.dims}.")
    x = _coord(p, p.dims[0])
    v = np.asarray(p.values, dtype=float)
    ok = np.isfinite(x) & np.isfinite(v)
    x, v = x[ok], v[ok]
    if x.size < 3:
        raise ValueError(f"{name} must hold at least 3 finite points, got {x.size}.")
    order = np.argsort(x, kind="stable")
    return x[order], v[order]


def _shock_on_profile(x, v, method, level, direction, name="profile") -> float:
    if method == "gradient":
        xf = 0.5 * (x[1:] + x[:-1])
        g = np.abs(np.diff(v) / np.diff(x))
        return _parabolic_peak(xf, g)
    lo, hi = float(v.min()), float(v.max())
    if level is None:
        level = 0.5 * (lo + hi)
    level = number("level", level)
    if not lo < level < hi:
        raise ValueError(f"level={level:g} must lie strictly inside the {name}'s range ({lo:g}, {hi:g}).")
    xc = _crossings(x, v, level)
    return float(xc[-1] if direction > 0 else xc[0])


def _method_direction(method, direction):
    if method not in ("gradient", "threshold"):
        raise ValueError(f"method must be 'gradient' or 'threshold', got {method!r}.")
    if direction not in (1, -1):
        raise ValueError(f"direction must be +1 (outermost = largest x) or -1 (smallest x), got {direction!r}.")


def shock_position(profile: xr.DataArray, method: str = "gradient", level: float | None = None, direction: int = +1) -> float:
    """Position of a shock on a 1D profile (along x, or along a radius).

    * ``method="gradient"``: the steepest point. With the one-sided slopes
      g_{i+½} = |v_{i+1} − v_i| / (x_{i+1} − x_i) placed at the midpoints
      x_{i+½}, the position is the vertex of the parabola through the
      largest g and its two neighbours (sub-cell; a discontinuity between
      two samples is placed exactly halfway between them).
    * ``method="threshold"``: the outermost crossing of ``level`` (default:
      halfway between the profile's minimum and maximum) by the piecewise
      linear interpolant, x* = x_i + (level − v_i)(x_{i+1} − x_i)/(v_{i+1} − v_i);
      outermost = largest x for ``direction=+1``, smallest for ``-1``.

    ``level`` and ``direction`` apply to the threshold method only. NaN
    points (solids) are dropped before either method. References: the
    shock-position measures of numerical shock studies, e.g. Toro 2009,
    *Riemann Solvers and Numerical Methods for Fluid Dynamics*, §6.4.

    Raises
    ------
    ValueError
        for a profile that is not 1D or has fewer than 3 finite points, an
        unknown method, direction other than ±1, or a level outside the
        profile's open range.
    """
    _method_direction(method, direction)
    x, v = _profile("profile", profile)
    return _shock_on_profile(x, v, method, level, direction)


def shock_radius(
    field2d: xr.DataArray,
    centre: tuple[float, float] = (0.0, 0.0),
    level: float | None = None,
    method: str = "threshold",
    ambient: float | None = None,
    bin_width: float | None = None,
) -> float:
    """Mean radius of the front of a cylindrical blast in a 2D (y, x) field.

    The field is azimuthally averaged in rings of width ``bin_width``
    (default: the larger cell spacing) about ``centre``: for ring k,
    r̄_k = mean radius of its cells and v̄_k = mean value of its finite cells
    (cells of a ring that lie outside the domain are simply absent, so a
    quarter-domain blast centred on a corner works). On that profile
    (r̄_k, v̄_k):

    * ``method="threshold"`` (default): the outermost crossing of
      ``level`` by linear interpolation, with

          level = ambient + ½ (peak − ambient),

      peak = max_k v̄_k, ambient = median of the field over the cells with
      r ≥ 0.9 r_max (r_max the largest cell radius) unless given;
    * ``method="gradient"``: the radius of the steepest radial slope,
      with the parabolic sub-cell fit of :func:`shock_position`;
    * ``method="front"``: the threshold crossing with the peak taken from
      the outermost wave alone: its foot is the outermost ring whose
      excess over ambient exceeds 1 % of the largest, its peak the largest
      v̄_k within a fifth of the foot's radius inside it. For a blast whose
      driver gas still holds more pressure than the air shock ahead of it
      (a dense core, early on) the plain threshold would find the driver's
      edge; for a Sedov-like profile, peaked at the front, both agree.

    Reference: the Sedov–Taylor blast-radius comparison (Sedov 1959,
    *Similarity and Dimensional Methods in Mechanics*, ch. IV; Kamm &
    Timmes 2007, LA-UR-07-2849).

    Raises
    ------
    ValueError
        for a field that is not 2D, a bad centre or bin width, an unknown
        method, or a level outside the ring profile's range.
    """
    if method not in ("gradient", "threshold", "front"):
        raise ValueError(f"method must be 'gradient', 'threshold' or 'front', got {method!r}.")
    rbar, vbar, rr, vv = _rings(field2d, centre, bin_width)
    if method == "gradient":
        return _shock_on_profile(rbar, vbar, "gradient", None, +1)
    if level is None:
        if ambient is None:
            ambient = float(np.median(vv[rr >= 0.9 * rr.max()]))
        ambient = number("ambient", ambient)
        peak = float(vbar.max())
        if method == "front":
            excess = vbar - ambient
            foot = rbar[np.flatnonzero(excess > 0.01 * excess.max())[-1]]
            peak = float(vbar[(rbar >= 0.8 * foot) & (rbar <= foot)].max())
        level = ambient + 0.5 * (peak - ambient)
    return _shock_on_profile(rbar, vbar, "threshold", level, +1, name="ring-averaged profile")


def ring_profile(field2d: xr.DataArray, centre: tuple[float, float] = (0.0, 0.0),
                 bin_width: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The azimuthal average of a 2D (y, x) field about ``centre`` in rings of
    width ``bin_width`` (default: the larger cell spacing): mean radius r̄_k
    and mean value v̄_k of the finite cells of each ring that holds any (a
    ring cut by the domain keeps the cells inside it)."""
    rbar, vbar, _, _ = _rings(field2d, centre, bin_width)
    return rbar, vbar


def _rings(field2d, centre, bin_width):
    """``(r̄, v̄)`` of :func:`ring_profile` and the radii and values of the finite cells."""
    f = _require_dataarray("field2d", field2d)
    if f.ndim != 2 or not {"x", "y"} <= set(f.dims):
        raise ValueError(f"field2d must be a 2D field on (y, x), got dims {f.dims}.")
    xc, yc = _pair("centre", centre, "(x, y)")
    f = f.transpose("y", "x")
    x, y = _coord(f, "x"), _coord(f, "y")
    v = np.asarray(f.values, dtype=float)
    r = np.hypot(x[None, :] - xc, y[:, None] - yc)
    if bin_width is None:
        spac = [float(np.median(np.abs(np.diff(c)))) for c in (x, y) if c.size > 1]
        if not spac:
            raise ValueError("field2d must have more than one cell along x or y.")
        bin_width = max(spac)
    bin_width = number("bin_width", bin_width)
    if bin_width <= 0:
        raise ValueError(f"bin_width must be > 0, got {bin_width:g}.")
    ok = np.isfinite(v)
    if not ok.any():
        raise ValueError("field2d is NaN everywhere.")
    rr, vv = r[ok], v[ok]
    k = np.floor(rr / bin_width).astype(np.int64)
    n = np.bincount(k)
    used = n > 0
    rbar = np.bincount(k, weights=rr)[used] / n[used]
    vbar = np.bincount(k, weights=vv)[used] / n[used]
    if rbar.size < 3:
        raise ValueError("field2d covers fewer than 3 rings about centre; check centre and bin_width.")
    return rbar, vbar, rr, vv


# ---------------------------------------------------------------------------
# probe series


def _fraction(name: str, x) -> float:
    x = number(name, x)
    if not 0.0 < x < 1.0:
        raise ValueError(f"{name} must lie in (0, 1), got {x:g}.")
    return x


def _arrival(t, v, baseline, threshold_fraction) -> tuple[float, int]:
    """Arrival time and the index of the first sample of the rise: the
    last sample before the maximum to cross the level from below."""
    vmax = float(v.max())
    if not vmax > baseline:
        raise ValueError(f"baseline={baseline:g} must lie below the series maximum {vmax:g}.")
    level = baseline + threshold_fraction * (vmax - baseline)
    top = int(np.argmax(v))
    below = np.flatnonzero(v[: top + 1] <= level)
    if below.size == 0:
        return float(t[0]), 0
    i = int(below[-1]) + 1
    ta = t[i - 1] + (level - v[i - 1]) * (t[i] - t[i - 1]) / (v[i] - v[i - 1])
    return float(ta), i


def arrival_time(series: xr.DataArray, baseline: float, threshold_fraction: float = 0.05) -> float:
    """The time a probe series rises above baseline + f (max − baseline) for
    good: its last upward crossing of that level before its maximum, so a
    noise spike ahead of the front (a particle method's scatter) does not
    count; for a clean front, the first crossing.

    With level = baseline + f (max_t v − baseline), f = ``threshold_fraction``,
    and i the first sample after the last one at or below the level before
    the maximum,

        t_a = t_{i−1} + (level − v_{i−1}) (t_i − t_{i−1}) / (v_i − v_{i−1}),

    the linear-interpolated crossing (t_a = t_0 if the first sample is
    already above). The usual time-of-arrival of blast measurements
    (Kinney & Graham 1985, *Explosive Shocks in Air*, ch. 6).

    Parameters
    ----------
    series : 1D DataArray on a time coordinate (NaN samples are dropped).
    baseline : the undisturbed value (e.g. p0).
    threshold_fraction : f in (0, 1).

    Raises
    ------
    ValueError
        for a series that is not 1D with ≥ 2 finite samples, f outside
        (0, 1), or a baseline not below the series maximum.
    """
    t, v = _series("series", series)
    baseline = number("baseline", baseline)
    f = _fraction("threshold_fraction", threshold_fraction)
    return _arrival(t, v, baseline, f)[0]


def _phase(t, v, baseline, threshold_fraction):
    ta, i = _arrival(t, v, baseline, threshold_fraction)
    above = v > baseline
    # start: the upward crossing of baseline just before the arrival
    below_before = np.nonzero(~above[:i])[0]
    if below_before.size:
        j = int(below_before[-1])
        start = t[j] + (baseline - v[j]) * (t[j + 1] - t[j]) / (v[j + 1] - v[j])
    else:
        j = -1
        start = float(t[0])
    # end: the first return to baseline after the arrival
    below_after = np.nonzero(~above[i:])[0]
    if below_after.size:
        k = i + int(below_after[0])
        end = t[k - 1] + (v[k - 1] - baseline) * (t[k] - t[k - 1]) / (v[k - 1] - v[k])
        truncated = False
        tt = np.concatenate(([start], t[j + 1 : k], [end]))
        vv = np.concatenate(([0.0], v[j + 1 : k] - baseline, [0.0]))
    else:
        end = float(t[-1])
        truncated = True
        head_t = [start] if j >= 0 else []
        head_v = [0.0] if j >= 0 else []
        tt = np.concatenate((head_t, t[j + 1 :]))
        vv = np.concatenate((head_v, v[j + 1 :] - baseline))
    impulse = float(np.trapezoid(vv, tt))
    return dict(duration=float(end - start), impulse=impulse, start=float(start), end=float(end),
                arrival=ta, truncated=truncated)


def positive_phase(series: xr.DataArray, baseline: float, threshold_fraction: float = 0.05) -> dict:
    """Positive-phase duration and impulse of a probe series.

    The positive phase runs from the upward crossing of ``baseline`` just
    before the arrival (see :func:`arrival_time`) to the first return to
    ``baseline`` after it, both crossings linearly interpolated; over it:

        I₊ = ∫ (v − baseline) dt     (trapezoid rule on the samples plus the
                                      two interpolated crossings),
        T₊ = t_end − t_start,

    as defined for blast waves by Baker 1973, *Explosions in Air*, §1 and
    Kinney & Graham 1985, ch. 6.

    Returns
    -------
    dict(duration=T₊, impulse=I₊, start=t_start, end=t_end, arrival=t_a,
    truncated=bool) — ``truncated`` is True when the series ends before it
    returns to baseline (then end = the last sample time).

    Raises
    ------
    ValueError
        as :func:`arrival_time`.
    """
    t, v = _series("series", series)
    baseline = number("baseline", baseline)
    f = _fraction("threshold_fraction", threshold_fraction)
    return _phase(t, v, baseline, f)


def peak(
    series: xr.DataArray,
    baseline: float,
    fit_window: tuple[float, float] | None = None,
    fit: str = "exponential",
    threshold_fraction: float = 0.05,
) -> dict:
    """Peak of a probe series: raw, and extrapolated back to the arrival.

    raw = max_t v. The raw maximum of a captured shock reflecting from a
    wall carries a start-up spike that does not shrink with resolution
    (SPEC §5; it differs from the physical peak by several per cent), so
    the peak is also read by a short least-squares fit just after the
    arrival t_a, skipping the first samples, and extrapolated back to t_a:

    * ``fit="exponential"`` (default): log(v − baseline) = c₀ + c₁ t,
      fitted = baseline + exp(c₀ + c₁ t_a). For a Friedlander wave
      v − baseline = P (1 − τ/T₊) e^{−α τ/T₊} the log is linear to first
      order in τ, so the default window's extrapolation bias is small: for
      α = 4 and the window 2–15 % of T₊ it is +0.33 % of P (log(1 − τ/T₊)
      is not linear), against −5.3 % for a linear fit of v itself.
    * ``fit="linear"``: v = c₀ + c₁ t, fitted = c₀ + c₁ t_a.

    Parameters
    ----------
    series : 1D DataArray on a time coordinate.
    baseline : the undisturbed value (e.g. p0).
    fit_window : (f0, f1), 0 ≤ f0 < f1 ≤ 1, default (0.02, 0.15)
        The fit uses the samples with t_a + f0 T₊ ≤ t ≤ t_a + f1 T₊,
        T₊ the positive-phase duration of :func:`positive_phase`.
    fit : "exponential" or "linear".
    threshold_fraction : passed to :func:`arrival_time`.

    Returns
    -------
    dict(raw=..., fitted=..., arrival=t_a, window=(t_lo, t_hi),
    n_fit=number of samples fitted).

    Raises
    ------
    ValueError
        for a bad window, an unknown fit, or fewer than 2 usable samples in
        the window ("widen fit_window or sample more often").
    """
    t, v = _series("series", series)
    baseline = number("baseline", baseline)
    f = _fraction("threshold_fraction", threshold_fraction)
    if fit not in ("exponential", "linear"):
        raise ValueError(f"fit must be 'exponential' or 'linear', got {fit!r}.")
    if fit_window is None:
        fit_window = (0.02, 0.15)
    f0, f1 = _pair("fit_window", fit_window, "(f0, f1) with 0 <= f0 < f1 <= 1")
    if not 0.0 <= f0 < f1 <= 1.0:
        raise ValueError(f"fit_window must be a pair (f0, f1) with 0 <= f0 < f1 <= 1, got ({f0:g}, {f1:g}).")
    ph = _phase(t, v, baseline, f)
    ta, dur = ph["arrival"], ph["duration"]
    lo, hi = ta + f0 * dur, ta + f1 * dur
    sel = (t >= lo) & (t <= hi)
    if fit == "exponential":
        sel &= v > baseline
    ts, vs = t[sel], v[sel]
    if ts.size < 2:
        raise ValueError(
            f"fit_window=({f0:g}, {f1:g}) holds {ts.size} usable sample(s) (need 2); widen fit_window or sample more often."
        )
    y = np.log(vs - baseline) if fit == "exponential" else vs
    c1, c0 = np.polyfit(ts - ta, y, 1)
    fitted = baseline + math.exp(c0) if fit == "exponential" else c0
    return dict(raw=float(v.max()), fitted=float(fitted), arrival=ta, window=(float(lo), float(hi)), n_fit=int(ts.size))


def first_crest(series: xr.DataArray, threshold_fraction: float = 0.1) -> dict:
    """The first crest of a wave record η(t): the first local maximum above
    ``threshold_fraction`` of the record's largest |η| (so the ripples of a
    quiet start do not count), refined by the parabola through it and its
    two neighbours, and its arrival: the last time before the crest at which
    η rises through half the crest's height (linear between samples; the
    front of a flat-topped wave, whose crest time means little). Returns
    ``{"height", "time", "arrival"}``; NaN for all if the record never rises
    above the threshold."""
    t, v = _series("series", series)
    level = _fraction("threshold_fraction", threshold_fraction) * float(np.max(np.abs(v)))
    rising = np.flatnonzero((v[1:-1] >= v[:-2]) & (v[1:-1] > v[2:]) & (v[1:-1] > level)) + 1
    if rising.size == 0 or level == 0.0:
        return {"height": float("nan"), "time": float("nan"), "arrival": float("nan")}
    k = int(rising[0])
    time, height = _vertex(t, v, k)
    below = np.flatnonzero(v[: k + 1] < 0.5 * height)
    arrival = float(t[0]) if below.size == 0 else float(_crossings(t[below[-1]:k + 1], v[below[-1]:k + 1],
                                                                   0.5 * height)[0])
    return {"height": height, "time": time, "arrival": arrival}


def plateau(series: xr.DataArray, t0: float, t1: float) -> float:
    """Time-mean of a series over [t0, t1] (e.g. a reflected-shock pressure).

        v̄ = (1/(t1 − t0)) ∫_{t0}^{t1} v(t) dt,

    with v the piecewise-linear interpolant of the samples (trapezoid rule,
    values at t0 and t1 interpolated), so a linear signal gives
    (v(t0) + v(t1))/2 exactly.

    Raises
    ------
    ValueError
        unless t_first ≤ t0 < t1 ≤ t_last of the series' finite samples.
    """
    t, v = _series("series", series)
    t0, t1 = number("t0", t0), number("t1", t1)
    if not t0 < t1:
        raise ValueError(f"t0={t0:g} must be smaller than t1={t1:g}.")
    if t0 < t[0] or t1 > t[-1]:
        raise ValueError(f"the window [t0, t1] = [{t0:g}, {t1:g}] must lie within the series' times [{t[0]:g}, {t[-1]:g}].")
    inner = (t > t0) & (t < t1)
    tt = np.concatenate(([t0], t[inner], [t1]))
    vv = np.concatenate(([np.interp(t0, t, v)], v[inner], [np.interp(t1, t, v)]))
    return float(np.trapezoid(vv, tt) / (t1 - t0))


# ---------------------------------------------------------------------------
# oblique shocks


def oblique_shock_angle(
    rho2d: xr.DataArray,
    apex: tuple[float, float],
    x_range: tuple[float, float],
    rho_free: float | None = None,
    rho_post: float | None = None,
    through_apex: bool = False,
) -> float:
    """Angle β (degrees, from the +x direction) of an oblique shock in a density field.

    For every column x_j in ``x_range`` (downstream of the wedge apex) the
    shock height y_s(x_j) is the highest crossing of

        level = ½ (rho_free + rho_post)

    by the linear interpolant in y (density is higher below the shock);
    rho_free defaults to the density in the top-left cell (largest y,
    smallest x) and rho_post to the median over the columns of the column
    maximum. A least-squares line y = c₀ + m x through the points
    (x_j, y_s) gives β = atan(m) (``through_apex=True`` forces the line
    through ``apex``: m = Σ(x−x_a)(y−y_a)/Σ(x−x_a)²). Compare with the
    θ–β–M relation tan θ = 2 cot β (M₁² sin²β − 1)/(M₁²(γ + cos 2β) + 2)
    (NACA Report 1135, 1953, eq. 139; Anderson, *Modern Compressible
    Flow*, §4.3). Cells inside the wedge are NaN and are never crossings.

    Raises
    ------
    ValueError
        for a field not on (y, x), x_range not inside the domain or not
        downstream of the apex, a level that no column crosses, or fewer
        than 2 columns with a crossing.
    """
    f = _require_dataarray("rho2d", rho2d)
    if f.ndim != 2 or not {"x", "y"} <= set(f.dims):
        raise ValueError(f"rho2d must be a 2D field on (y, x), got dims {f.dims}.")
    f = f.transpose("y", "x")
    xa, ya = _pair("apex", apex, "(x, y)")
    x0, x1 = _pair("x_range", x_range, "(x0, x1)")
    x, y = _coord(f, "x"), _coord(f, "y")
    if not (x0 < x1):
        raise ValueError(f"x_range=({x0:g}, {x1:g}) must have x0 < x1.")
    if x0 < xa:
        raise ValueError(f"x_range=({x0:g}, {x1:g}) must start at or downstream of the apex x={xa:g}.")
    cols = (x >= x0) & (x <= x1)
    if cols.sum() < 2:
        raise ValueError(f"x_range=({x0:g}, {x1:g}) must hold at least 2 columns of the grid (x from {x.min():g} to {x.max():g}).")
    yorder = np.argsort(y)
    y = y[yorder]
    v = np.asarray(f.values, dtype=float)[yorder]
    if rho_free is None:
        rho_free = v[-1, int(np.argmin(x))]
    rho_free = number("rho_free (the top-left cell by default)", rho_free)
    xs = x[cols]
    vc = v[:, cols]
    if rho_post is None:
        with np.errstate(invalid="ignore"):
            colmax = np.nanmax(np.where(np.isfinite(vc), vc, -np.inf), axis=0)
        colmax = colmax[np.isfinite(colmax)]
        if colmax.size == 0:
            raise ValueError("rho2d is NaN in every column of x_range.")
        rho_post = float(np.median(colmax))
    rho_post = number("rho_post", rho_post)
    if rho_post == rho_free:
        raise ValueError(f"rho_post must differ from rho_free (both {rho_free:g}).")
    level = 0.5 * (rho_free + rho_post)
    s = vc - level
    lo, hi = s[:-1], s[1:]
    with np.errstate(invalid="ignore"):
        cross = np.isfinite(lo) & np.isfinite(hi) & ((lo < 0) != (hi < 0))
    jidx = np.where(cross, np.arange(s.shape[0] - 1)[:, None], -1).max(axis=0)
    have = jidx >= 0
    if have.sum() < 2:
        raise ValueError(
            f"only {int(have.sum())} column(s) in x_range cross level={level:g} between rho_free and rho_post; need 2."
        )
    j = jidx[have]
    ci = np.nonzero(have)[0]
    v0, v1 = vc[j, ci], vc[j + 1, ci]
    ys = y[j] + (level - v0) * (y[j + 1] - y[j]) / (v1 - v0)
    xp = xs[have]
    if through_apex:
        dx_, dy_ = xp - xa, ys - ya
        m = float(np.sum(dx_ * dy_) / np.sum(dx_ * dx_))
    else:
        m = float(np.polyfit(xp, ys, 1)[0])
    return math.degrees(math.atan(m))


# ---------------------------------------------------------------------------
# conservation


def conservation_drift(totals) -> float:
    """Relative drift of a conserved total: max_t |q(t) − q(0)| / |q(0)|.

    ``totals`` is the time history of a domain integral (mass, momentum,
    energy) of a closed-domain run; the drift should sit at round-off for
    the conservative FV and DSMC schemes (SPEC §9).

    Raises
    ------
    ValueError
        for an empty or non-1D array, non-finite entries, or q(0) = 0.
    """
    q = np.asarray(totals, dtype=float)
    if q.ndim != 1 or q.size < 1:
        raise ValueError(f"totals must be a non-empty 1D array, got shape {q.shape}.")
    if not np.all(np.isfinite(q)):
        raise ValueError("totals must be finite (it holds NaN or inf).")
    if q[0] == 0.0:
        raise ValueError("totals[0] must be non-zero (the drift is relative to it).")
    return float(np.max(np.abs(q - q[0])) / abs(q[0]))


def schlieren(rho: xr.DataArray, k: float = 15.0) -> xr.DataArray:
    """Numerical schlieren of a 2D density field on ``(y, x)``:

        S = exp(−k |∇ρ| / max |∇ρ|),

    |∇ρ| by second-order central differences (one-sided at the edges) on the
    field's own coordinates; NaN cells (solids) stay NaN and are left out of
    the maximum (Quirk 1994, "A contribution to the great Riemann solver
    debate", Int. J. Numer. Meth. Fluids 18, 555). Dark (S → 0) where the
    density changes fastest, 1 where it is uniform."""
    rho = _require_dataarray("rho", rho)
    if rho.dims != ("y", "x"):
        raise ValueError(f"rho must be a 2D field on (y, x), got dims {rho.dims}.")
    k = number("k", k)
    if not k > 0:
        raise ValueError(f"k must be > 0, got {k:g}.")
    gy, gx = np.gradient(rho.values, _coord(rho, "y"), _coord(rho, "x"))
    magnitude = np.hypot(gx, gy)
    top = np.nanmax(magnitude) if np.any(np.isfinite(magnitude)) else 0.0
    shade = np.exp(-k * magnitude / top) if top > 0 else np.ones_like(magnitude)
    return xr.DataArray(shade, coords=rho.coords, dims=rho.dims, name="schlieren",
                        attrs={"long_name": f"numerical schlieren exp(-{k:g} |grad rho| / max |grad rho|)", "units": "1"})
