"""Which cells of the coarse grid hold particles, and where particles go in them.

The hybrid method (Myers, Musk, Palmer & Palmer 2024, Front. Phys. 11,
1325294) puts SPH particles only in the cells that need them: those where
density or pressure jumps by more than a threshold between face neighbours
(:func:`sensed_jumps`: pressure alone leaves contacts to the grid, pressure
across compressing faces leaves all but shocks), widened by a buffer of
cells (:func:`flagged`); a ring of
cells around them, as wide as the supports of the particles near it
reach, holds the boundary particles (:func:`ring`). Particles
are laid out on the injection map of a cell, a square lattice of
``per_cell`` points per axis (:func:`lattice`), and laid out again where
too few are left or one has grown too coarse (:func:`relaid`).

Fields are in the layout ``([y,] x)`` and cells are numbered in that
order (flat index ``j nx + i`` in 2D).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage


def relative_jumps(a: np.ndarray, periodic, velocity=None) -> np.ndarray:
    """The largest relative jump |a_c − a_n| / min(a_c, a_n) from each cell
    to its face neighbours ``n`` (``periodic``: per axis x[, y]; the field
    layout is ``([y,] x)``). With ``velocity`` (its components along x[, y],
    in the field layout) only faces the flow does not diverge across count
    (u_n,right ≤ u_n,left): a shock compresses, while the flow behind a
    blast, a rarefaction and a contact do not."""
    jumps = np.zeros_like(a)
    for axis in range(a.ndim):
        wraps = periodic[a.ndim - 1 - axis]
        b = np.roll(a, -1, axis=axis)
        jump = np.abs(b - a) / np.minimum(a, b)
        if velocity is not None:
            un = velocity[a.ndim - 1 - axis]
            jump = np.where(np.roll(un, -1, axis=axis) <= un, jump, 0.0)
        if not wraps:  # no neighbour beyond the last cell
            jump[(slice(None),) * axis + (-1,)] = 0.0
        jumps = np.maximum(jumps, np.maximum(jump, np.roll(jump, 1, axis=axis)))
    return jumps


def dilated(mask: np.ndarray, cells: int, periodic) -> np.ndarray:
    """``mask`` grown by ``cells`` cells in every direction (diagonals
    included), wrapping around periodic axes."""
    if cells <= 0 or not mask.any():
        return mask.copy()
    pad = [(cells, cells) if periodic[mask.ndim - 1 - axis] else (0, 0) for axis in range(mask.ndim)]
    grown = ndimage.binary_dilation(np.pad(mask, pad, mode="wrap"), np.ones((3,) * mask.ndim, bool), cells)
    return grown[tuple(slice(lo, grown.shape[k] - hi) for k, (lo, hi) in enumerate(pad))]


def sensed_jumps(W: np.ndarray, sensor: str, periodic) -> np.ndarray:
    """The jumps of the primitive fields ``W`` (ρ, u[, v], p; layout
    ``([y,] x)``) that flag cells, by ``sensor``: ``"rho,p"`` the larger
    relative jump of density or pressure (shocks and contacts), ``"p"``
    of pressure (shocks and rarefactions; contacts stay on the grid),
    ``"shock"`` of pressure across faces the flow does not diverge across
    (shocks alone: behind a blast the flow expands and goes to the grid)."""
    if sensor == "rho,p":
        return np.maximum(relative_jumps(W[0], periodic), relative_jumps(W[-1], periodic))
    if sensor == "p":
        return relative_jumps(W[-1], periodic)
    return relative_jumps(W[-1], periodic, W[1:-1])


#: the settings of ``sensor`` (:func:`sensed_jumps`)
SENSORS = ("rho,p", "p", "shock")


def flagged(jumps: np.ndarray, threshold: float, buffer: int, periodic) -> np.ndarray:
    """The cells that get particles: a jump (:func:`sensed_jumps`) above
    ``threshold``, plus ``buffer`` cells around."""
    return dilated(jumps > threshold, buffer, periodic)


def ring(inner: np.ndarray, reach: np.ndarray, periodic) -> np.ndarray:
    """The cells not in ``inner`` within ``reach[c]`` cells (chessboard
    distance, diagonals included) of some cell ``c``: each cell's reach
    spread outwards, one less per cell crossed (a 3×3 maximum filter,
    wrapping around periodic axes)."""
    modes = ["wrap" if periodic[reach.ndim - 1 - axis] else "constant" for axis in range(reach.ndim)]
    spread = reach.astype(np.int64)
    for _ in range(int(spread.max(initial=0))):
        spread = np.maximum(spread, ndimage.maximum_filter(spread, size=3, mode=modes, cval=0) - 1)
    return (spread > 0) & ~inner


def cell_of(x: np.ndarray, lo, dx, shape) -> np.ndarray:
    """Flat index of the cell holding each position ``x`` (n, d) on the grid
    with lower corner ``lo``, cell sizes ``dx`` and ``shape`` (per axis x[, y]);
    positions outside are put in the nearest cell."""
    index = np.zeros(x.shape[0], np.int64)
    stride = 1
    for d in range(x.shape[1]):
        i = np.clip(np.floor((x[:, d] - lo[d]) / dx[d]).astype(np.int64), 0, shape[d] - 1)
        index += stride * i
        stride *= shape[d]
    return index


def lattice(cells: np.ndarray, lo, dx, shape, per_cell: int) -> tuple[np.ndarray, np.ndarray]:
    """The injection map of the flat cells ``cells``: ``per_cell`` points per
    axis at the centres of a square sub-lattice of each cell; returns the
    points (n, d) and the cell each lies in."""
    dim = len(shape)
    sub = (np.arange(per_cell) + 0.5) / per_cell
    offsets = np.stack(np.meshgrid(*([sub] * dim), indexing="ij"), axis=-1).reshape(-1, dim)
    corner = np.empty((cells.size, dim))
    rest = cells.copy()
    for d in range(dim):
        corner[:, d] = lo[d] + dx[d] * (rest % shape[d])
        rest //= shape[d]
    points = (corner[:, None, :] + offsets[None, :, :] * np.asarray(dx, float)).reshape(-1, dim)
    return points, np.repeat(cells, offsets.shape[0])


def thinned(cell: np.ndarray, n_cells: int, fewest: float) -> np.ndarray:
    """Per cell, whether fewer than ``fewest`` of the particles in the flat
    cells ``cell`` lie in it."""
    return np.bincount(cell, minlength=n_cells) < fewest


def relaid(cell: np.ndarray, m: np.ndarray, rho: np.ndarray, n_cells: int, lattice_count: int,
           cell_volume: float, coarsest: float) -> np.ndarray:
    """Per cell, whether its particles (in the flat cells ``cell``, with
    masses ``m`` and densities ``rho``) should give way to the cell's
    lattice: fewer than a quarter of the ``lattice_count`` points are left,
    or one particle carries more than ``coarsest`` times the mass a lattice
    particle would carry at its density, ρ V_cell / lattice_count (dense gas
    expanded into rarefied gas, whose support H = η (m/ρ)^(1/d) spans many
    lattice spacings)."""
    thin = thinned(cell, n_cells, 0.25 * lattice_count)
    coarse = np.zeros(n_cells, bool)
    coarse[cell[m > coarsest * rho * cell_volume / lattice_count]] = True
    return thin | coarse
