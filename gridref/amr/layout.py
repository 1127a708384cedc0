"""The static shape of a block-structured hierarchy (Berger & Colella 1989,
J. Comput. Phys. 82, 64): ``levels`` levels of refinement ratio 2, each
tiled by square blocks of ``block`` cells a side.

Level 0 covers the domain with ``coarse`` cells per axis; level ``l`` has
``coarse · 2ˡ`` and spacing ``dx · 2^(levels−1−l)`` (``dx`` the finest).
Every level is stored block-major, one array per variable of shape
``(blocks, block[, block])`` with the block index ``by · nbx + bx`` (x
fastest) and the cells inside a block in the field layout ``([y,] x)``;
only its active blocks are advanced. A block of level ``l`` has ``2^dim``
children on level ``l + 1`` (its halves along every axis), which is why a
level's cells per axis must be a whole number of blocks on every level:
``coarse`` must be a multiple of ``block`` (level 0 is tiled too).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from partmesh.cases.errors import InputError

#: the block sizes a hierarchy chooses from when none is given, best first (ghost layers of 2 cells cost
#: (1 + 4/B)^dim of the cells updated: 1.56 at 16 in 2D)
PREFERRED_BLOCKS = (16, 32, 20, 24, 12, 8, 40, 48, 64, 10, 6, 4)


@dataclass(frozen=True)
class Layout:
    """``levels`` levels of ratio 2 over ``coarse`` level-0 cells per axis
    (x first), blocks of ``block`` cells a side, finest spacing ``dx`` [m]
    per axis, the domain's lower corner ``origin`` and its boundary kinds
    per side (x_lo, x_hi[, y_lo, y_hi]: ``reflect``, ``outflow``,
    ``periodic``, ``inflow``)."""

    levels: int
    block: int
    coarse: tuple[int, ...]
    dx: tuple[float, ...]
    origin: tuple[float, ...]
    kinds: tuple[str, ...]

    @property
    def dim(self) -> int:
        return len(self.coarse)

    @property
    def periodic(self) -> tuple[bool, ...]:
        return tuple(self.kinds[2 * d] == "periodic" for d in range(self.dim))

    def cells(self, level: int) -> tuple[int, ...]:
        """Cells per axis of ``level`` (x first)."""
        return tuple(n << level for n in self.coarse)

    def blocks(self, level: int) -> tuple[int, ...]:
        """Blocks per axis of ``level`` (x first)."""
        return tuple(n // self.block for n in self.cells(level))

    def n_blocks(self, level: int) -> int:
        return math.prod(self.blocks(level))

    def spacing(self, level: int) -> tuple[float, ...]:
        """Cell size per axis of ``level`` [m]."""
        return tuple(h * (1 << (self.levels - 1 - level)) for h in self.dx)

    @property
    def block_shape(self) -> tuple[int, ...]:
        """A block's cells in the field layout ``([y,] x)``."""
        return (self.block,) * self.dim

    @property
    def cells_per_block(self) -> int:
        """The cells of a block."""
        return self.block ** self.dim

    def face_shape(self, d: int) -> tuple[int, ...]:
        """A block's faces normal to axis ``d``, laid out ``([y,] x)``."""
        B = self.block
        if self.dim == 1:
            return (B + 1,)
        return (B, B + 1) if d == 0 else (B + 1, B)

    @property
    def edge_shape(self) -> tuple[int, ...]:
        """A block's faces on its two boundaries normal to one axis: ``(2[, block])``."""
        return (2, self.block) if self.dim == 2 else (2,)

    def cell_index(self, level: int, at):
        """The flat index, into ``level``'s block-major storage raveled, of
        the cells at global indices ``at`` (per axis, x first; numpy or JAX
        integer arrays)."""
        if self.dim == 1:
            return at[0]
        B, (x, y) = self.block, at
        return ((y // B) * self.blocks(level)[0] + x // B) * (B * B) + (y % B) * B + x % B

    def cell_centres(self, level: int) -> list[np.ndarray]:
        """Cell-centre coordinates along each axis of ``level`` (x first)."""
        h = self.spacing(level)
        return [o + (np.arange(n) + 0.5) * s for o, n, s in zip(self.origin, self.cells(level), h)]


def coords_of(ids, nb: tuple[int, ...], xp=np) -> tuple:
    """Per-axis block coordinates (x first) of flat block ids on a level
    of ``nb`` blocks per axis (x fastest)."""
    if len(nb) == 1:
        return (ids,)
    by, bx = xp.divmod(ids, nb[0])
    return bx, by


def flat_id(coords, nb: tuple[int, ...]):
    """The flat block id of per-axis block coordinates (x first)."""
    return coords[0] if len(nb) == 1 else coords[1] * nb[0] + coords[0]


def block_size_for(coarse: tuple[int, ...], block: int | None, levels: int) -> int:
    """The block size of a hierarchy whose level 0 has ``coarse`` cells per
    axis: ``block`` checked (an even number of cells that tiles level 0),
    or the first of :data:`PREFERRED_BLOCKS` that does."""
    fits = [b for b in PREFERRED_BLOCKS if all(n % b == 0 for n in coarse)]
    if block is None:
        if not fits:
            raise InputError(_no_block(coarse, levels))
        return fits[0]
    if block % 2 or block < 4 or any(n % block for n in coarse):
        allowed = ", ".join(str(b) for b in sorted(fits)) or "none"
        raise InputError(f"block = {block} must be an even number of cells (at least 4) that divides the coarsest "
                         f"level's {' x '.join(map(str, coarse))} cells ({levels} levels); allowed here: {allowed}.")
    return block


def _no_block(coarse, levels) -> str:
    return (f"levels = {levels} leaves the coarsest level {' x '.join(map(str, coarse))} cells, which no block size "
            f"of {min(PREFERRED_BLOCKS)} to {max(PREFERRED_BLOCKS)} cells tiles: use fewer levels or a dx that "
            "divides the domain into a multiple of 16 (or 8) cells per axis on the coarsest level.")


def layout_for(domain, dx: float, levels: int, kinds, block: int | None = None) -> Layout:
    """The layout of ``levels`` levels over ``domain`` (``((lo, hi), ...)``)
    whose finest spacing is ``dx``, with the boundary ``kinds`` per side;
    refused in one sentence when the finest grid is not a whole number of
    coarsest cells, or no block size tiles the coarsest level."""
    finest = []
    for axis, (lo, hi) in zip("xy", domain):
        n = (hi - lo) / dx
        if abs(n - round(n)) > 1e-6 * n or round(n) < 1:
            raise InputError(f"dx = {dx:g} m does not divide the domain extent along {axis} ({hi - lo:g} m) into "
                             "whole cells.")
        finest.append(int(round(n)))
    ratio = 1 << (levels - 1)
    if any(n % ratio for n in finest):
        raise InputError(f"levels = {levels} needs the finest grid ({' x '.join(map(str, finest))} cells at dx = "
                         f"{dx:g} m) to be a multiple of 2^(levels-1) = {ratio} cells per axis.")
    coarse = tuple(n // ratio for n in finest)
    b = block_size_for(coarse, block, levels)
    return Layout(levels=levels, block=b, coarse=coarse, dx=(dx,) * len(coarse),
                  origin=tuple(lo for lo, _ in domain), kinds=tuple(kinds))
