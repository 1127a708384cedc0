"""The uniform cell-centred grid of a solver (:class:`Grid`), the solver
grid of a scene at a requested cell size, and helpers over it."""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from partmesh.cases.errors import InputError
from partmesh.compare.regrid import linear_weights


@dataclass(frozen=True)
class Grid:
    """``shape`` cells per axis (x first) over ``domain``, ``((lo, hi), ...)``
    per axis: cells of ``step = (hi − lo) / n`` whose centres lie at
    ``lo + (i + ½) step`` (:func:`cell_centres`)."""

    shape: tuple[int, ...]
    domain: tuple[tuple[float, float], ...]

    def __post_init__(self):
        object.__setattr__(self, "shape", tuple(int(n) for n in self.shape))
        object.__setattr__(self, "domain", tuple((float(lo), float(hi)) for lo, hi in self.domain))

    @property
    def step(self) -> tuple[float, ...]:
        return tuple((hi - lo) / n for (lo, hi), n in zip(self.domain, self.shape))

    @property
    def ndim(self) -> int:
        return len(self.shape)


def solver_grid(domain: tuple[tuple[float, float], ...], dx: float) -> Grid:
    """A uniform cell-centred grid over ``domain`` with square cells of size
    ``dx``; each extent must hold a whole number of cells (to 1e-6)."""
    shape = []
    for axis, (lo, hi) in zip("xyz", domain):
        n = (hi - lo) / dx
        if abs(n - round(n)) > 1e-6 * n or round(n) < 1:
            raise InputError(
                f"dx = {dx:g} m does not divide the domain extent along {axis} ({hi - lo:g} m) into whole cells."
            )
        shape.append(int(round(n)))
    return Grid(tuple(shape), tuple(domain))


def cropped(a, axes, k=1):
    """The array ``a`` with ``k`` cells removed at both ends of every axis in
    ``axes`` (ghost layers off a padded field)."""
    index = [slice(None)] * a.ndim
    for axis in axes:
        index[axis] = slice(k, a.shape[axis] - k)
    return a[tuple(index)]


def cell_centres(grid: Grid) -> list[np.ndarray]:
    """Cell-centre coordinates along each axis (x first): ``lo + (i + ½) Δx``."""
    return [lo + (np.arange(n) + 0.5) * step for (lo, _), n, step in zip(grid.domain, grid.shape, grid.step)]


def mesh(grid: Grid) -> tuple[np.ndarray | None, ...]:
    """Cell-centre coordinate arrays in the field layout ``([[z,] y,] x)``:
    ``(x, None)`` in 1D, ``(X, Y)`` in 2D, ``(X, Y, Z)`` in 3D."""
    axes = cell_centres(grid)
    if len(axes) == 1:
        return axes[0], None
    return tuple(np.meshgrid(*axes[::-1], indexing="ij")[::-1])


def bilinear_stencil(grid: Grid, points: np.ndarray,
                     periodic=(False, False, False)) -> tuple[np.ndarray, np.ndarray]:
    """Flat indices ``(n, 2**dim)`` into the field layout ``([[z,] y,] x)`` and the
    (bi-, tri-)linear interpolation weights of the cell centres around each of the
    ``points`` ``(n, dim)``; along a ``periodic`` axis (x, y, z) the stencil
    wraps around, elsewhere points beyond the outermost centres take the
    edge value (clamped). The corners run with x fastest."""
    points = np.atleast_2d(np.asarray(points, float))
    axes = cell_centres(grid)
    per_axis = [linear_weights(c, h, points[:, d], bool(periodic[d]) if d < len(periodic) else False)
                for d, (c, h) in enumerate(zip(axes, grid.step))]
    strides = np.cumprod([1, *grid.shape[:-1]])
    index, weight = [], []
    for corner in itertools.product((0, 1), repeat=len(axes)):  # z (if any) slowest, x fastest
        bits = corner[::-1]  # (x, y, z)
        index.append(sum(s * (hi if b else lo) for s, b, (lo, hi, _) in zip(strides, bits, per_axis)))
        weight.append(np.prod([f if b else 1 - f for b, (_, _, f) in zip(bits, per_axis)], axis=0))
    return np.stack(index, axis=1), np.stack(weight, axis=1)
