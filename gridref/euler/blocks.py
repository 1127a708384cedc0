"""One MUSCL–Hancock step of one level of a block-structured hierarchy
(:mod:`partmesh.gridref.amr.hierarchy`): every active block read with two
ghost layers from the level's storage (:mod:`partmesh.gridref.amr.windows`)
and advanced by the kernels of :mod:`partmesh.gridref.euler.step`, in
chunks of blocks laid side by side (:mod:`partmesh.gridref.amr.tiling`),
with the same a-posteriori positivity
fallback and vacuum floors as a uniform grid
(:func:`~partmesh.gridref.euler.step.with_fallbacks`): a hierarchy whose
every block is active steps exactly as the uniform grid does. In a
geometry of revolution every cell of a chunk reads the face areas, volume
and hoop term of its global radius (:class:`~partmesh.gridref.revolution.RadialTable`).
"""

from __future__ import annotations

from dataclasses import replace

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.gridref.amr.hierarchy import Hierarchy, Levels, with_level
from partmesh.gridref.amr.layout import coords_of, flat_id
from partmesh.gridref.amr.tiling import chunk_for, rows_for, tiled, windowed
from partmesh.gridref.amr.windows import Sources, block_origins, gathered, sources
from partmesh.gridref.euler.boundaries import N_GHOST
from partmesh.gridref.euler.state import primitive
from partmesh.gridref.euler.cut_blocks import CutBlocks
from partmesh.gridref.euler.step import (Scheme, Stepper, face_flux, flux_divergence, flux_update, half_step,
                                         slopes_of, stable_dt, vacuum_floored, with_fallbacks)
from partmesh.gridref.grid import cropped
from partmesh.gridref.revolution import REVOLUTION
from partmesh.gridref.staging import staged


def admissible(gamma):
    """The states a prolongation may make: positive density and pressure."""
    def ok(U):
        W = primitive(U, gamma)
        return (W[0] > 0.0) & (W[-1] > 0.0)
    return ok


def sensed(gamma):
    """What the error estimator reads of a gas: density and pressure."""
    def variables(U):
        W = primitive(U, gamma)
        return W[0], W[-1]
    return variables


class LevelStepper:
    """The step of one level: ``step(H, level, dt, imposed) -> (H, dt_next,
    forces)`` with ``dt_next`` the level's CFL step after it (NaN: not
    physical), ``forces`` the gas's force on every side of the domain
    through the level's faces there that no finer level covers, and ``H``
    with the level advanced, its step's old state and fluxes kept for the
    finer level and the refluxing, and its boundary fluxes added to its
    register (:class:`~partmesh.gridref.amr.hierarchy.Hierarchy`)."""

    def __init__(self, levels: Levels, scheme: Scheme, cut: CutBlocks | None = None):
        self.levels, self.layout = levels, levels.layout
        #: the cut cells of the bodies, on the finest level (:mod:`partmesh.gridref.euler.cut_blocks`)
        self.cut = cut
        self.schemes = [replace(scheme, dx=self.layout.spacing(level)) for level in range(self.layout.levels)]
        self.gamma = scheme.gamma
        self.tables = levels.tables  # (two ghost cells beyond either end: N_GHOST)

    def _cut_of(self, level: int) -> CutBlocks | None:
        """The bodies' cut cells if ``level`` holds them (the finest), else None."""
        return self.cut if level == self.layout.levels - 1 else None

    def crowding(self, level: int, ids):
        """The CFL rate's factor of revolution of every cell of the blocks
        ``ids`` of ``level`` (None when planar)."""
        table = self.tables[level]
        if table is None:
            return None
        x = self.levels.radii(level, ids)
        return table.crowding_at(x if self.layout.dim == 1 else x[:, None, :])

    def volumes(self, level: int, ids):
        """The volume of every cell of the blocks ``ids`` of ``level`` [m³ per
        metre depth in planar 2D, m per square metre in 1D; of revolution,
        the whole ring]."""
        volume = float(np.prod(self.layout.spacing(level)))
        table = self.tables[level]
        if table is None:
            return volume
        x = self.levels.radii(level, ids)
        return volume * REVOLUTION[self.levels.radial] * table.volumes_at(x if self.layout.dim == 1 else x[:, None, :])

    def _tiled_coords(self, level: int, ids, rows: int):
        """The global cell indices (x, y; unwrapped) of the windows of the
        blocks ``ids`` with two ghost layers, tiled side by side."""
        lay, h = self.layout, self.layout.block + 2 * N_GHOST
        bx, by = coords_of(ids, lay.blocks(level), jnp)
        lanes = jnp.arange(h) - N_GHOST
        X = jnp.broadcast_to((bx * lay.block)[:, None, None] + lanes[None, None, :], (ids.shape[0], h, h))
        Y = jnp.broadcast_to((by * lay.block)[:, None, None] + lanes[None, :, None], (ids.shape[0], h, h))
        return tiled(X, rows), tiled(Y, rows)

    def _tiled_rings(self, level: int, ids, rows: int):
        """The :class:`~partmesh.gridref.revolution.Rings` of the chunk of
        blocks ``ids`` tiled side by side (None when planar)."""
        table, lay = self.tables[level], self.layout
        if table is None:
            return None
        h = lay.block + 2 * N_GHOST
        x = self.levels.radii(level, ids, -N_GHOST, h)
        if lay.dim == 2:
            x = jnp.broadcast_to(x[:, None, :], (x.shape[0], h, h))
        x = tiled(x, rows)
        return table.rings(x[(slice(1, -1),) * x.ndim])

    def step(self, H: Hierarchy, level: int, dt, imposed):
        lay, scheme, gamma, levels = self.layout, self.schemes[level], self.gamma, self.levels
        ids, count = H.active[level]
        n, B = ids.shape[0], lay.block
        K = chunk_for(n, lay.cells_per_block)
        rows, h = rows_for(K), B + 2 * N_GHOST
        valid = jnp.arange(n) < count
        fluid = jnp.broadcast_to(valid.reshape((n,) + (1,) * lay.dim), (n, *lay.block_shape))
        cut = self._cut_of(level)
        if cut is not None:
            fluid = fluid & jnp.asarray(cut.fluid)[ids]
        gate = jnp.isfinite(dt)
        U0 = levels.blocks_of(H.U[level], ids)
        images = None if cut is None else staged(lambda U: cut.images(U, gamma), gate)(H.U[level])
        ring = tuple(b + 2 for b in lay.block_shape)  # a block and one ghost layer: where ``ok`` lives
        faces = [lay.face_shape(d) for d in range(lay.dim)]
        stores_fluxes = level < lay.levels - 1  # (a level with a finer one keeps Δt F for the refluxing)

        crowding = self.crowding(level, ids)

        def chunk(c, allowed):
            """The step of the ``K`` blocks of chunk ``c``, tiled side by side, and
            (without bodies) the CFL step of its new state."""
            chunk_ids = jax.lax.dynamic_slice(ids, (c * K,), (K,))
            fluid_c, crowding_c = (None if a is None else jax.lax.dynamic_slice_in_dim(a, c * K, K)
                                   for a in (fluid, crowding))
            src = self._tiled_sources(level, chunk_ids, N_GHOST, rows)
            rings = self._tiled_rings(level, chunk_ids, rows)
            Ug = staged(lambda U, imposed: gathered(U, src, imposed), gate)(H.U[level], imposed)
            Wg = staged(lambda Ug: primitive(Ug, gamma), gate)(Ug)
            if cut is not None:
                Wg = staged(lambda Wg, images: cut.filled(Wg, src.index, images), gate)(Wg, images)
            slopes = staged(lambda Wg: slopes_of(Wg, scheme), gate)(Wg)
            allowed = staged(lambda a: _tiled_ring(a, rows), gate)(allowed)
            Wh, ok = staged(lambda Wg, s, allowed: half_step(Wg, s, dt, scheme, allowed, rings), gate)(
                Wg, slopes, allowed)
            fluxes = [staged(lambda Wh, s, ok, d=d: face_flux(Wh, s, ok, d, scheme), gate)(Wh, slopes[d], ok)
                      for d in range(lay.dim)]

            def updated(Ug, F, Wh, ok, fluid_c, crowding_c):
                inner = tuple(cropped(u, scheme.axes, N_GHOST) for u in Ug)
                if cut is None:
                    U_new = flux_update(inner, F, dt, scheme, Wh, rings=rings)[0]
                    D = ()
                else:
                    U_new, D = self._cut_update(cut, inner, F, Wh, dt, scheme, src,
                                                self._tiled_coords(level, chunk_ids, rows))
                F = [tuple(windowed(f, rows, K, h, faces[d]) for f in Fd) for d, Fd in enumerate(F)]
                U_new = tuple(windowed(u, rows, K, h, lay.block_shape) for u in U_new)
                # (with bodies the state changes again, by the redistribution: its CFL step is taken after it)
                dt_c = stable_dt(U_new, gamma, scheme.dx, scheme.cfl, fluid_c, crowding_c) if cut is None else ()
                return (U_new, [tuple(_boundary_faces(f, d, lay.dim) for f in Fd) for d, Fd in enumerate(F)],
                        windowed(ok, rows, K, h, ring), tuple(windowed(a, rows, K, h, lay.block_shape) for a in D),
                        F if stores_fluxes else (), dt_c)

            return staged(updated, gate)(Ug, fluxes, Wh, ok, fluid_c, crowding_c)

        def cfl_dt(U):
            return stable_dt(U, gamma, scheme.dx, scheme.cfl, fluid, crowding)

        def attempt(allowed, previous):
            # the last attempt's pools of the new state and boundary fluxes, overwritten block by block (no copy
            # of them); a level with a finer one writes Δt F into its flux storage as each chunk is done
            pools = (previous[0], previous[2], jnp.zeros((n, *ring), bool),
                     tuple(jnp.zeros((n, *lay.block_shape)) for _ in U0) if cut else ())

            def body(c, carry):
                pools, stored, dt_min = carry
                U_c, faces_c, ok_c, D_c, F_c, dt_c = chunk(c, jax.lax.dynamic_slice_in_dim(allowed, c * K, K))
                pools = jax.tree_util.tree_map(lambda pool, part: jax.lax.dynamic_update_slice_in_dim(
                    pool, part, c * K, 0), pools, (U_c, faces_c, ok_c, D_c))
                if stores_fluxes:
                    chunk_ids = jax.lax.dynamic_slice_in_dim(ids, c * K, K)
                    stored = tuple(levels.with_blocks(S, chunk_ids, [dt * f for f in F]) for S, F in zip(stored, F_c))
                # (the least CFL step of the chunks is the level's: cfl / max rate, as over all blocks at once)
                return pools, stored, dt_min if cut is not None else jnp.minimum(dt_min, dt_c)

            (U_new, faces, ok, D), stored, dt_next = jax.lax.fori_loop(0, (count + K - 1) // K, body,
                                                                       (pools, previous[3], jnp.array(jnp.inf)))
            if cut is not None:  # redistribution and merging: the cells near the walls, from their neighbours' D
                def redistributed(U_new, D):
                    D = levels.with_blocks(levels.empty(level), ids, D)
                    return cut.redistributed(U_new, H.U[level], D, dt, _positions(ids, lay.n_blocks(level)))

                U_new = staged(redistributed, gate)(U_new, D)
                dt_next = staged(cfl_dt, gate)(U_new)
            return (U_new, dt_next, faces, stored), ok

        def allowed_after(ok, U_new):
            return staged(lambda ok, U_new: self._second_order_allowed(ok, U_new, level, ids, fluid), gate)(
                ok, U_new)

        volume = self.volumes(level, ids) * (1.0 if cut is None else jnp.asarray(cut.volume)[ids])

        def floored(U):
            U, cells, mass, energy = vacuum_floored(U, gamma, fluid)
            return U, cfl_dt(U), cells, jnp.sum(mass * volume), jnp.sum(energy * volume)

        start = (tuple(jnp.zeros_like(u) for u in U0), jnp.zeros(()),
                 [tuple(jnp.zeros((n, *lay.edge_shape)) for _ in U0) for _ in range(lay.dim)],
                 H.flux[level] if stores_fluxes else ())
        (U_new, dt_next, faces, stored), added = with_fallbacks(attempt, allowed_after, staged(floored, gate),
                                                                jnp.ones((n, *ring), bool), Stepper.RETRIES, start)
        H = self._advanced(H, level, ids, U0, U_new, faces, stored, dt)
        forces = self._side_forces(H, level, ids, valid, faces)
        H = H._replace(floors=H.floors + added, updates=H.updates + count * np.prod(lay.block_shape))
        return H, dt_next, forces

    @staticmethod
    def _cut_update(cut: CutBlocks, U, F, Wh, dt, scheme: Scheme, src: Sources, coords):
        """``(U − Δt D in the open cells, D)`` of the interior ``U`` of tiled
        windows (their cells' global indices ``coords``) with the fluxes ``F``
        through the open parts of its faces and the walls' pressure from the
        half-step state ``Wh``
        (:func:`~partmesh.gridref.euler.step.cut_cell_divergence`)."""
        fluid, is_cut, wall, normal = cut.window_fields(src.index, src.outside)
        D, _ = flux_divergence(F, scheme, cut.apertures(*coords))
        inner = (slice(N_GHOST, -N_GHOST),) * 2
        W = tuple(cropped(a, scheme.axes) for a in Wh)
        walls = cut.wall_divergence(W, is_cut[inner], tuple(b[inner] for b in wall), tuple(m[inner] for m in normal),
                                    scheme.gamma, scheme.riemann)
        D = [d + w for d, w in zip(D, walls)]
        return tuple(jnp.where(fluid[inner], u - dt * d, u) for u, d in zip(U, D)), tuple(D)

    def _tiled_sources(self, level, ids, ghosts, rows) -> Sources:
        """The sources of the windows of the blocks ``ids`` with ``ghosts``
        layers, laid side by side (:mod:`partmesh.gridref.amr.tiling`)."""
        lay = self.layout
        src = sources(lay, level, block_origins(lay, level, ids, -ghosts), lay.block + 2 * ghosts)
        shape = src.index.shape

        def tile(a):
            return None if a is None else tiled(jnp.broadcast_to(a, shape), rows)

        return Sources(tile(src.index), tuple(tile(f) for f in src.flips), tile(src.inflow), tile(src.outside))

    def _second_order_allowed(self, ok, U_new, level, ids, fluid):
        """``ok`` (every block and one ghost layer) without the cells at or
        next to a cell whose new state is not physical, in this block or a
        neighbour (as :func:`~partmesh.gridref.euler.step.second_order_allowed`
        on a whole grid: no cell beyond a side of the domain counts)."""
        W = primitive(U_new, self.gamma)
        bad = (~(W[0] > 0.0) | ~(W[-1] > 0.0)) & fluid
        lay = self.layout
        stored = jnp.zeros((lay.n_blocks(level), *lay.block_shape), bool).at[ids].set(bad, mode="drop")
        src = sources(lay, level, block_origins(lay, level, ids, -2), lay.block + 4)
        around = stored.ravel()[src.index] & ~src.outside
        for axis in range(1, around.ndim):  # grown by one cell along every axis, diagonals included
            around = around | jnp.roll(around, 1, axis) | jnp.roll(around, -1, axis)
        return ok & ~around[(slice(None),) + (slice(1, -1),) * lay.dim]

    def _advanced(self, H, level, ids, U0, U_new, faces, stored, dt):
        """``H`` with the level's blocks set to ``U_new``; for a level with a
        finer one, its old state and Δt F (``stored``, its flux storage with
        the step's blocks written) kept; for one with a coarser one, Δt F
        through its blocks' boundary faces (``faces``) added to its register."""
        levels, L = self.levels, self.layout.levels
        U = levels.with_blocks(H.U[level], ids, U_new)
        H = H._replace(U=with_level(H.U, level, U))
        if level < L - 1:
            H = H._replace(old=with_level(H.old, level, levels.with_blocks(H.old[level], ids, U0)),
                           flux=with_level(H.flux, level, stored))
        if level > 0:
            register = tuple(tuple(r + dt * f for r, f in zip(reg, F))
                             for reg, F in zip(H.register[level], faces))
            H = H._replace(register=with_level(H.register, level, register))
        return H

    def _side_forces(self, H, level, ids, valid, faces):
        """The normal momentum flux through the level's faces on every side
        of the domain (x_lo, x_hi[, y_lo, y_hi]) that no finer level covers,
        times their area (per metre depth in 2D, per square metre in 1D; of
        revolution, the whole revolved side), from the fluxes through the
        blocks' boundary faces ``faces``."""
        lay = self.layout
        nb = lay.blocks(level)
        coords = coords_of(ids, nb, jnp)
        open_ = jnp.broadcast_to(valid.reshape((-1,) + (1,) * lay.dim), valid.shape + lay.block_shape)
        if level < lay.levels - 1:
            open_ = open_ & ~_covered(H.maps[level + 1], ids, lay, level)
        dx = lay.spacing(level)
        table, k = self.tables[level], self.levels.radial
        forces = []
        for d in range(lay.dim):
            momentum = faces[d][1 + d]  # (n, 2[, B])
            edge = _boundary_faces(open_, d, lay.dim)
            area = 1.0 if lay.dim == 1 else dx[1 - d]
            for side, at_side in ((0, coords[d] == 0), (1, coords[d] == nb[d] - 1)):
                m = momentum[:, side]
                mask = edge[:, side] & at_side.reshape((-1,) + (1,) * (m.ndim - 1))
                if self._cut_of(level) is not None:  # the open parts of the faces
                    m = m * self.cut.side_apertures(d, side, *coords, lay.block)
                if table is None:
                    forces.append(jnp.sum(jnp.where(mask, m, 0.0)) * area)
                    continue
                # the revolved side: each face's area (a side normal to r), or its cell's ring (normal to z)
                ring = (table.areas_at(coords[0] * lay.block + side * lay.block)[:, None] if d == 0
                        else table.volumes_at(self.levels.radii(level, ids)))
                weight = REVOLUTION[k] * area * (ring if lay.dim == 2 else ring[:, 0])
                forces.append(jnp.sum(jnp.where(mask, m * weight, 0.0)))
        return jnp.stack(forces)


def _positions(ids, n_blocks: int):
    """Where every block of a level's ``n_blocks`` sits in its list ``ids``
    (those not listed, and the list's padding: anywhere)."""
    return jnp.zeros(n_blocks + 1, jnp.int32).at[ids].set(jnp.arange(ids.shape[0], dtype=jnp.int32))


def _tiled_ring(a, rows: int):
    """Per-block masks of a block and one ghost layer (k, B+2[, B+2]) laid
    out as the cells one layer into tiled windows of two ghost layers
    (the layout of the slopes and the predictor)."""
    width = [(0, 0)] + [(0, 2)] * (a.ndim - 1)
    t = tiled(jnp.pad(a, width), rows)
    return t[tuple(slice(0, n - 2) for n in t.shape)]


def _boundary_faces(F, d: int, dim: int):
    """A batch of blocks' fluxes through their two boundary faces normal to
    axis ``d``: (n, 2[, B]) from (n, B + 1) or (n, B[, B + 1]) / (n, B + 1, B)."""
    if dim == 1:
        return jnp.stack([F[:, 0], F[:, -1]], axis=1)
    if d == 0:
        return jnp.stack([F[:, :, 0], F[:, :, -1]], axis=1)
    return jnp.stack([F[:, 0, :], F[:, -1, :]], axis=1)


def _covered(maps_fine, ids, lay, level):
    """Per cell of the blocks ``ids`` of ``level``: whether a block of the
    finer level covers it."""
    coords = coords_of(ids, lay.blocks(level), jnp)
    nb_f = lay.blocks(level + 1)
    half = lay.block // 2
    offsets = jnp.arange(2)
    flat = maps_fine.ravel()
    if lay.dim == 1:
        kids = flat[2 * coords[0][:, None] + offsets[None, :]]  # (n, 2)
        return jnp.repeat(kids, half, axis=1)
    cx = 2 * coords[0][:, None, None] + offsets[None, None, :]
    cy = 2 * coords[1][:, None, None] + offsets[None, :, None]
    kids = flat[flat_id((cx, cy), nb_f)]  # (n, 2, 2)
    return jnp.repeat(jnp.repeat(kids, half, axis=1), half, axis=2)

