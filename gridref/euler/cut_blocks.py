"""The conservative cut cells of :mod:`partmesh.gridref.euler.immersed` on
the finest level of a block-structured hierarchy, whose blocks that meet a
body are always active.

The cut-cell geometry is built once on the finest level's whole grid
(:func:`~partmesh.gridref.euler.immersed.immersed_boundary`) and laid out
as the level's block-major storage: the open volume fraction κ, the wall
vector and normal of every cut cell (zero elsewhere), the image-point tables of the ghost cells
inside the bodies, the redistribution neighbourhoods and the merged groups,
every flat index mapped from the grid to the storage; the faces'
apertures stay the whole grid's, read by global index. A step of the level
then does what the uniform grid's cut-cell step does
(:func:`~partmesh.gridref.euler.step.cut_cell_divergence`,
:meth:`~partmesh.gridref.euler.immersed.ImmersedBoundary.advanced`), with
the same arithmetic on the same numbers:

1. the ghost cells' image states from the level's storage, set into each
   tiled chunk of blocks after its conversion to primitive variables;
2. per chunk, the fluxes through the open parts of the faces and the
   walls' pressure: ``D``, and ``U − Δt D`` in every open cell;
3. after every chunk, the few cells whose update redistribution or
   merging changes, from the ``D`` of their neighbourhoods.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.gridref.amr.layout import Layout
from partmesh.gridref.euler.immersed import ImmersedBoundary, band_sum, mirrored_images, wall_pressure
from partmesh.gridref.euler.state import primitive


class CutBlocks:
    """The cut cells of ``immersed`` (on the whole grid of ``level``) in
    the block-major storage of ``layout``'s ``level``."""

    def __init__(self, immersed: ImmersedBoundary, layout: Layout, level: int):
        ib, lay = immersed, layout
        ny, nx = ib.shape
        B = lay.block
        self.n_blocks, self.cells_per_block = lay.n_blocks(level), B * B
        size = self.n_blocks * self.cells_per_block
        iy, ix = np.divmod(np.arange(ny * nx), nx)
        # the storage index of every cell of the grid, and one past the last for the grid's own sentinel
        self._to_storage = np.append(lay.cell_index(level, (ix, iy)), size)

        def stored(field):
            out = np.zeros(size, np.asarray(field).dtype)
            out[self._to_storage[:-1]] = np.asarray(field).ravel()
            return out.reshape(self.n_blocks, B, B)

        self.shape, self.periodic = ib.shape, ib.periodic
        #: the apertures of every face of the grid (x faces (ny, nx + 1), y faces (ny + 1, nx))
        self.face_apertures = ib.apertures
        self.volume = stored(ib.volume)
        self.fluid = self.volume > 0.0
        wall, wall_normal = (np.zeros((2, ny * nx)) for _ in range(2))
        wall[:, ib.cut], wall_normal[:, ib.cut] = ib.wall, ib.wall_normal
        cut = np.zeros(ny * nx, bool)
        cut[ib.cut] = True
        self.cut = stored(cut)
        self.wall = tuple(stored(w) for w in wall)
        self.wall_normal = tuple(stored(n) for n in wall_normal)
        self.ghost, self.stencil, self.weights, self.normal = (self.storage_index(ib.ghost),
                                                               self.storage_index(ib.stencil), ib.weights, ib.normal)
        slot = np.full(size, -1, np.int32)
        slot[self.ghost] = np.arange(self.ghost.size)
        #: per storage cell, its place among the ghost cells (−1: not a ghost)
        self.slot = slot
        givers, giver_nb, band, band_nb = ib.redistribution
        self.givers, self.giver_nb = self.storage_index(givers), self.storage_index(giver_nb)
        self.band, self.band_nb = self.storage_index(band), self.storage_index(band_nb)
        self._kappa_g, self._around_g, self._others_g = ib.open_volumes(givers, giver_nb)
        self._kappa_b, self._around_b, self._others_b = ib.open_volumes(band, band_nb)
        members, self.label = ib.merged
        self.members = self.storage_index(members)
        self._member_volume = ib.volume.ravel()[members]
        self.n_groups = int(self.label.max()) + 1 if members.size else 0
        blocks = np.zeros(size, bool)
        near = np.concatenate([self.ghost, self.stencil.ravel(), self.band, self.givers, self.members,
                               np.flatnonzero(~self.fluid.ravel())])
        blocks[near[near < size]] = True
        #: blocks that hold a solid, cut, ghost, stencil or redistributing cell
        self.blocks = blocks.reshape(self.n_blocks, -1).any(axis=1)

    def storage_index(self, flat) -> np.ndarray:
        """Storage indices of flat indices of the whole grid (its sentinel, one
        past the last cell, to the storage's)."""
        return self._to_storage[np.asarray(flat)]

    # --- 1. the ghost cells -------------------------------------------------------------------------
    def images(self, U, gamma):
        """The primitive state of every ghost cell: its image point's,
        bilinear from the open cells of the level's storage ``U``, with the
        normal velocity reversed (as :meth:`ImmersedBoundary.fill`)."""
        W = primitive(tuple(u.ravel()[self.stencil] for u in U), gamma)
        return mirrored_images(W, self.weights, self.normal)

    def filled(self, Wg, index, images):
        """The primitive windows ``Wg`` with every ghost cell (``index``: each
        window cell's storage index) set to its image state."""
        slot = jnp.asarray(self.slot)[index]
        at = jnp.maximum(slot, 0)
        return tuple(jnp.where(slot >= 0, g[at], w) for w, g in zip(Wg, images))

    # --- 2. the chunk's right-hand side -------------------------------------------------------------
    def window_fields(self, index, outside):
        """The open mask, the cut mask, the wall vector and normal of every
        window cell (``index``: its storage index; ``outside``: beyond a side
        of the domain, where no wall lies)."""
        def read(a, beyond):
            return jnp.where(outside, beyond, jnp.asarray(a).ravel()[index])

        return (read(self.fluid, True), read(self.cut, False), tuple(read(w, 0.0) for w in self.wall),
                tuple(read(n, 0.0) for n in self.wall_normal))

    def apertures(self, X, Y):
        """The apertures of the faces a step of tiled windows with two ghost
        layers computes (x faces (R−4, W−3), y faces (R−3, W−4)), from the
        global cell indices ``X``, ``Y`` of the windows' cells (unwrapped;
        a face is the lower face of the cell above it)."""
        (ny, nx), (px, py) = self.shape, self.periodic
        ax, ay = (jnp.asarray(a) for a in self.face_apertures)

        def along(i, n, wrap, faces):
            """Indices ``i`` along an axis of ``n`` cells (``faces``: of its n + 1 faces), wrapped or clipped."""
            return jnp.mod(i, n) if wrap else jnp.clip(i, 0, n if faces else n - 1)

        x_faces = ax[along(Y[2:-2, 2:-1], ny, py, False), along(X[2:-2, 2:-1], nx, px, True)]
        y_faces = ay[along(Y[2:-1, 2:-2], ny, py, True), along(X[2:-1, 2:-2], nx, px, False)]
        return x_faces, y_faces

    def side_apertures(self, d: int, side: int, bx, by, B: int):
        """The apertures of the boundary faces of blocks at block coordinates
        ``bx``, ``by`` normal to axis ``d`` on their ``side`` (0 lower, 1
        upper): (n, B)."""
        ax, ay = (jnp.asarray(a) for a in self.face_apertures)
        lanes = jnp.arange(B)[None, :]
        if d == 0:
            return ax[by[:, None] * B + lanes, (bx[:, None] + side) * B]
        return ay[(by[:, None] + side) * B, bx[:, None] * B + lanes]

    @staticmethod
    def wall_divergence(W, cut, wall, wall_normal, gamma, riemann):
        """The walls' part of ``D`` in every cell of the interior ``W``
        (primitive, the half-step state): ``(0, p_w B/V, 0)`` where ``cut``,
        zero elsewhere (as :meth:`ImmersedBoundary.wall_divergence`)."""
        p_wall = wall_pressure(W, wall_normal, gamma, riemann)
        zero = jnp.zeros_like(W[0])
        return (zero, *(jnp.where(cut, p_wall * b, 0.0) for b in wall), zero)

    # --- 3. redistribution and merging --------------------------------------------------------------
    def redistributed(self, U_new, U_old, D, dt, position):
        """``U_new`` (the level's active blocks, each at ``position`` of its
        storage block in the list) with the band cells advanced by the
        hybrid divergence and the shares their neighbours give
        (:meth:`ImmersedBoundary.advanced`), from the old state ``U_old`` and
        ``D`` of the level's storage, and every merged group set to its
        volume-weighted mean."""
        givers, band = self.givers, self.band
        kappa_g, around_g, others_g = self._kappa_g, self._around_g, self._others_g
        kappa_b, around_b, others_b = self._kappa_b, self._around_b, self._others_b
        at_band = self._in_list(band, position)
        out = []
        for u_new, u, Dv in zip(U_new, U_old, D):
            average = band_sum(Dv, self.giver_nb) / np.where(around_g > 0.0, around_g, 1.0)
            deficit = jnp.where(others_g > 0.0, (1.0 - kappa_g) * (Dv.ravel()[givers] - kappa_g * average), 0.0)
            shares = jnp.zeros(Dv.size).at[givers].set(deficit / np.where(others_g > 0.0, others_g, 1.0))
            average = band_sum(Dv, self.band_nb) / np.where(around_b > 0.0, around_b, 1.0)
            D_band = Dv.ravel()[band]
            hybrid = jnp.where(others_b > 0.0, D_band + (1.0 - kappa_b) * average,
                               D_band / np.where(kappa_b > 0.0, kappa_b, 1.0))
            gained = band_sum(shares.reshape(Dv.shape), self.band_nb) - shares[band]
            value = u.ravel()[band] - dt * (hybrid + gained)
            out.append(u_new.ravel().at[at_band].set(value, mode="drop").reshape(u_new.shape))
        return self._mixed(tuple(out), position)

    def _mixed(self, U, position):
        """``U`` (the active blocks) with every merged group at its mean Σ κ U / Σ κ."""
        if self.members.size == 0:
            return U
        at = self._in_list(self.members, position)
        volume = np.bincount(self.label, weights=self._member_volume, minlength=self.n_groups)
        out = []
        for u in U:
            flat = u.ravel()
            total = jax.ops.segment_sum(self._member_volume * flat[at], self.label, self.n_groups)
            out.append(flat.at[at].set((total / volume)[self.label], mode="drop").reshape(u.shape))
        return tuple(out)

    def _in_list(self, cells, position):
        """Flat indices into the active blocks' arrays of the storage ``cells``
        (``position[b]``: where storage block ``b`` sits in the list)."""
        block, cell = np.divmod(cells, self.cells_per_block)
        return position[block] * self.cells_per_block + cell

