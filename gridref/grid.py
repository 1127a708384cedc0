"""Helpers around :class:`jax_cfd.base.grids.Grid`: the solver grid of a
scene at a requested cell size."""

from __future__ import annotations

import numpy as np
from jax_cfd.base import grids

from partmesh.cases.errors import InputError
from partmesh.compare.regrid import linear_weights


def solver_grid(domain: tuple[tuple[float, float], ...], dx: float) -> grids.Grid:
    """A uniform cell-centred grid over ``domain`` with square cells of size
    ``dx``; each extent must hold a whole number of cells (to 1e-6)."""
    shape = []
    for axis, (lo, hi) in zip("xy", domain):
        n = (hi - lo) / dx
        if abs(n - round(n)) > 1e-6 * n or round(n) < 1:
            raise InputError(
                f"dx = {dx:g} m does not divide the domain extent along {axis} ({hi - lo:g} m) into whole cells."
            )
        shape.append(int(round(n)))
    return grids.Grid(tuple(shape), domain=tuple(domain))


def cropped(a, axes, k=1):
    """The array ``a`` with ``k`` cells removed at both ends of every axis in
    ``axes`` (ghost layers off a padded field)."""
    index = [slice(None)] * a.ndim
    for axis in axes:
        index[axis] = slice(k, a.shape[axis] - k)
    return a[tuple(index)]


def cell_centres(grid: grids.Grid) -> list[np.ndarray]:
    """Cell-centre coordinates along each axis (x first)."""
    return [np.asarray(a) for a in grid.axes()]


def mesh(grid: grids.Grid) -> tuple[np.ndarray, np.ndarray | None]:
    """Cell-centre coordinate arrays in the field layout ``([y,] x)``:
    ``(X, Y)`` in 2D, ``(x, None)`` in 1D."""
    axes = cell_centres(grid)
    if len(axes) == 1:
        return axes[0], None
    Y, X = np.meshgrid(axes[1], axes[0], indexing="ij")
    return X, Y


def bilinear_stencil(grid: grids.Grid, points: np.ndarray, periodic=(False, False)) -> tuple[np.ndarray, np.ndarray]:
    """Flat indices ``(n, 2**dim)`` into the field layout ``([y,] x)`` and the
    (bi)linear interpolation weights of the cell centres around each of the
    ``points`` ``(n, dim)``; along a ``periodic`` axis (x, y) the stencil
    wraps around, elsewhere points beyond the outermost centres take the
    edge value (clamped)."""
    points = np.atleast_2d(np.asarray(points, float))
    axes = cell_centres(grid)
    lower, upper, frac = zip(*(linear_weights(c, h, points[:, d], periodic[d])
                               for d, (c, h) in enumerate(zip(axes, grid.step))))
    if len(axes) == 1:
        return np.stack([lower[0], upper[0]], axis=1), np.stack([1 - frac[0], frac[0]], axis=1)
    nx = grid.shape[0]
    (i, j), (i1, j1), (fx, fy) = lower, upper, frac
    idx = np.stack([j * nx + i, j * nx + i1, j1 * nx + i, j1 * nx + i1], axis=1)
    w = np.stack([(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy], axis=1)
    return idx, w
