"""The checks and small operations the measures share: a DataArray and its
coordinate, a (lo, hi) pair, a fraction, a probe series, the crossings of
a level and the vertex of a parabola through three samples."""

from __future__ import annotations

import numpy as np
import xarray as xr

from partmesh.compare.checks import number


def dataarray(name: str, a) -> xr.DataArray:
    """``a`` itself if it is a DataArray, or a ValueError naming ``name``."""
    if not isinstance(a, xr.DataArray):
        raise ValueError(f"{name} must be an xarray.DataArray, got {type(a).__name__}.")
    return a


def coordinate(a: xr.DataArray, dim: str) -> np.ndarray:
    """The values of ``a``'s coordinate along ``dim`` as floats (its index where it has none)."""
    return np.asarray(a[dim].values, dtype=float) if dim in a.coords else np.arange(a.sizes[dim], dtype=float)


def pair(name: str, v, what: str = "(a, b)") -> tuple[float, float]:
    """Two finite numbers, or a ValueError naming ``name``."""
    try:
        items = list(v)
    except TypeError:
        items = None
    if items is None or len(items) != 2:
        raise ValueError(f"{name} must be a pair {what} of numbers, got {v!r}.")
    return number(name, items[0]), number(name, items[1])


def crossings(x: np.ndarray, v: np.ndarray, level: float) -> np.ndarray:
    """All positions where the piecewise-linear interpolant of (x, v) equals
    ``level`` (sample points equal to level count once), sorted."""
    s = v - level
    on = s == 0.0
    between = (s[:-1] * s[1:] < 0.0)
    i = np.nonzero(between)[0]
    xc = x[i] + (level - v[i]) * (x[i + 1] - x[i]) / (v[i + 1] - v[i])
    return np.sort(np.concatenate((xc, x[on])))


def vertex(x: np.ndarray, g: np.ndarray, i: int) -> tuple[float, float]:
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


def parabolic_peak(x: np.ndarray, g: np.ndarray) -> float:
    """Vertex of the parabola through the maximum of g and its two neighbours."""
    return vertex(x, g, int(np.argmax(g)))[0]


def sorted_samples(name: str, a, what: str, samples: str, at_least: int) -> tuple[np.ndarray, np.ndarray]:
    """(coordinate, value) of the 1D DataArray ``a``, NaN samples dropped,
    sorted along the coordinate; a ValueError naming ``name`` where ``a``
    is not 1D (it must be ``what``) or holds fewer than ``at_least``
    finite ``samples``."""
    a = dataarray(name, a)
    if a.ndim != 1:
        raise ValueError(f"{name} must be {what}, got dims {a.dims}.")
    x = coordinate(a, a.dims[0])
    v = np.asarray(a.values, dtype=float)
    ok = np.isfinite(x) & np.isfinite(v)
    x, v = x[ok], v[ok]
    if x.size < at_least:
        raise ValueError(f"{name} must hold at least {at_least} finite {samples}, got {x.size}.")
    order = np.argsort(x, kind="stable")
    return x[order], v[order]


def time_series(name: str, series) -> tuple[np.ndarray, np.ndarray]:
    """(t, v) of a 1D time series DataArray, NaN samples dropped, sorted in t."""
    t, v = sorted_samples(name, series, "a 1D time series (select one probe first)", "samples", 2)
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"{name} has repeated sample times; its time coordinate must be strictly increasing.")
    return t, v


def fraction(name: str, x) -> float:
    x = number(name, x)
    if not 0.0 < x < 1.0:
        raise ValueError(f"{name} must lie in (0, 1), got {x:g}.")
    return x
