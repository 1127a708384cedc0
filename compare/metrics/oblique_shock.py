"""The angle of an oblique shock from a 2D density field (the ``wedge``
scene against the θ–β–M relation)."""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from partmesh.compare.checks import number
from partmesh.compare.metrics.samples import coordinate, dataarray, pair


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
    f = dataarray("rho2d", rho2d)
    if f.ndim != 2 or not {"x", "y"} <= set(f.dims):
        raise ValueError(f"rho2d must be a 2D field on (y, x), got dims {f.dims}.")
    f = f.transpose("y", "x")
    xa, ya = pair("apex", apex, "(x, y)")
    x0, x1 = pair("x_range", x_range, "(x0, x1)")
    x, y = coordinate(f, "x"), coordinate(f, "y")
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
