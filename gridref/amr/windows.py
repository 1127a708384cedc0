"""Windows of cells around blocks, gathered from a level's block-major
storage, with the domain's boundary ghosts.

A window is a square of ``size`` cells a side whose lower corner sits at a
global cell index per axis (a block's cells and two ghost layers; a child
block's footprint on its parent level and one cell around it). Cells of the
window inside the domain are read from the storage wherever they lie (in
the block itself or in its neighbours); cells beyond a side follow that
side's rule, as :func:`partmesh.gridref.euler.boundaries.with_ghosts` pads a
whole grid, x first and then y (a corner takes the y rule applied to the x
ghosts): ``periodic`` wraps, ``reflect`` mirrors and negates the normal
momentum, ``outflow`` repeats the edge cell, ``inflow`` takes the side's
imposed state. The index arithmetic runs on the device with the gather, so
a window follows its block wherever regridding moves it.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax.numpy as jnp

from partmesh.gridref.amr.layout import Layout, coords_of


@dataclass(frozen=True)
class Sources:
    """Where every cell of a batch of windows comes from: ``index`` (flat,
    into the level's storage raveled), ``flips`` (per axis: the momentum
    along that axis is negated), ``inflow`` (the side whose imposed state
    the cell takes, −1 for none) and ``outside`` (the cell lies beyond a
    side of the domain)."""

    index: jnp.ndarray
    flips: tuple
    inflow: jnp.ndarray | None
    outside: jnp.ndarray


def _axis_rule(G, n: int, d: int, kinds):
    """For global cell indices ``G`` along axis ``d`` of ``n`` cells: the
    index each reads, whether it mirrors (flip), the inflow side it takes
    (−1: none) and whether it lies beyond a side."""
    below, above = G < 0, G >= n
    m, flip, inflow = G, jnp.zeros(G.shape, bool), jnp.full(G.shape, -1, jnp.int32)
    for side, beyond, mirror, edge in ((2 * d, below, -1 - G, 0), (2 * d + 1, above, 2 * n - 1 - G, n - 1)):
        kind = kinds[side]
        if kind == "periodic":
            m = jnp.where(beyond, jnp.mod(G, n), m)
        elif kind == "reflect":
            m = jnp.where(beyond, mirror, m)
            flip = flip | beyond
        elif kind == "outflow":
            m = jnp.where(beyond, edge, m)
        elif kind == "inflow":
            m = jnp.where(beyond, edge, m)
            inflow = jnp.where(beyond, side, inflow)
        else:
            raise ValueError(f"unknown boundary kind {kind!r}")
    return m, flip, inflow, below | above


def sources(layout: Layout, level: int, origins, size: int) -> Sources:
    """The :class:`Sources` of windows of ``size`` cells a side on
    ``level`` whose lower corners are at the global cell indices
    ``origins`` (per axis, x first, each of shape (n,))."""
    cells = layout.cells(level)
    offsets = jnp.arange(size)
    rules = [_axis_rule(o[:, None] + offsets, cells[d], d, layout.kinds) for d, o in enumerate(origins)]
    if layout.dim == 1:
        (m, flip, inflow, outside), = rules
        has_inflow = "inflow" in layout.kinds
        return Sources(m, (flip,), inflow if has_inflow else None, outside)
    (mx, fx, ix, ox), (my, fy, iy, oy) = rules
    mx, fx, ix, ox = (a[:, None, :] for a in (mx, fx, ix, ox))  # (n, 1, size): along x, the last axis
    my, fy, iy, oy = (a[:, :, None] for a in (my, fy, iy, oy))  # (n, size, 1)
    index = layout.cell_index(level, (mx, my))
    if "inflow" not in layout.kinds:
        return Sources(index, (fx, fy), None, ox | oy)
    from_y = iy >= 0
    inflow = jnp.where(from_y, iy, ix)
    from_any = inflow >= 0
    return Sources(index, (fx & ~from_any, fy & ~from_y), inflow, ox | oy)


def block_origins(layout: Layout, level: int, ids, lo: int) -> tuple:
    """The window corners ``lo`` cells beyond the lower corner of every block
    ``ids`` of ``level`` (per axis, x first)."""
    return tuple(c * layout.block + lo for c in coords_of(ids, layout.blocks(level), jnp))


def gathered(storage, src: Sources, imposed=None):
    """The conservative state of every window cell (a tuple over variables
    of arrays shaped like ``src.index``), from ``storage`` (a tuple of the
    level's block-major arrays) and the conservative ``imposed`` state of
    every side (a (sides, variables) array; only inflow sides are read)."""
    out = [a.ravel()[src.index] for a in storage]
    if src.inflow is not None:
        side = jnp.maximum(src.inflow, 0)
        out = [jnp.where(src.inflow >= 0, imposed[side, k], a) for k, a in enumerate(out)]
    for d, flip in enumerate(src.flips):
        out[1 + d] = jnp.where(flip, -out[1 + d], out[1 + d])
    return tuple(out)
