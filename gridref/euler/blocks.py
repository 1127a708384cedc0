"""One MUSCL–Hancock step of one level of a block-structured hierarchy
(:mod:`partmesh.gridref.amr.hierarchy`): every active block read with two
ghost layers from the level's storage (:mod:`partmesh.gridref.amr.windows`)
and advanced by the kernels of :mod:`partmesh.gridref.euler.step`, batched
over the blocks (``jax.vmap``), with the same a-posteriori positivity
fallback and vacuum floors as a uniform grid
(:func:`~partmesh.gridref.euler.step.with_fallbacks`): a hierarchy whose
every block is active steps exactly as the uniform grid does.
"""

from __future__ import annotations

from dataclasses import replace

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.gridref.amr.hierarchy import Hierarchy, Levels
from partmesh.gridref.amr.layout import coords_of
from partmesh.gridref.amr.windows import block_origins, sources
from partmesh.gridref.euler.boundaries import N_GHOST
from partmesh.gridref.euler.state import primitive
from partmesh.gridref.euler.step import (Scheme, _dilated, face_flux, flux_update, half_step, slopes_of, stable_dt,
                                         vacuum_floored, with_fallbacks)
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


def _vmapped(kernel, *static):
    """``kernel`` over a leading axis of blocks (``static``: arguments shared by all)."""
    return jax.vmap(lambda *a: kernel(*a, *static))


class LevelStepper:
    """The step of one level: ``step(H, level, dt, imposed) -> (H, dt_next,
    forces)`` with ``dt_next`` the level's CFL step after it (NaN: not
    physical), ``forces`` the gas's force on every side of the domain
    through the level's faces there that no finer level covers, and ``H``
    with the level advanced, its step's old state and fluxes kept for the
    finer level and the refluxing, and its boundary fluxes added to its
    register (:class:`~partmesh.gridref.amr.hierarchy.Hierarchy`)."""

    RETRIES = 2

    def __init__(self, levels: Levels, scheme: Scheme):
        self.levels, self.layout = levels, levels.layout
        self.schemes = [replace(scheme, dx=self.layout.spacing(level)) for level in range(self.layout.levels)]
        self.gamma = scheme.gamma

    def step(self, H: Hierarchy, level: int, dt, imposed):
        lay, scheme, gamma, levels = self.layout, self.schemes[level], self.gamma, self.levels
        ids, count = H.active[level]
        cap = ids.shape[0]
        valid = jnp.arange(cap) < count
        fluid = jnp.broadcast_to(valid.reshape((cap,) + (1,) * lay.dim), (cap, *lay.block_shape))
        gate = jnp.isfinite(dt)
        U0 = levels.blocks_of(H.U[level], ids)
        Wg = staged(lambda U, imposed: primitive(levels.windows(U, level, ids, N_GHOST, imposed), gamma), gate)(
            H.U[level], imposed)
        slopes = staged(_vmapped(slopes_of, scheme), gate)(Wg)

        def cfl_dt(U):
            return stable_dt(U, gamma, scheme.dx, scheme.cfl, fluid)

        def attempt(allowed):
            Wh, ok = staged(lambda Wg, s, allowed: jax.vmap(lambda w, sl, al: half_step(w, sl, dt, scheme, al))(
                Wg, s, allowed), gate)(Wg, slopes, allowed)
            fluxes = [staged(lambda Wh, s, ok, d=d: jax.vmap(lambda w, sl, o: face_flux(w, sl, o, d, scheme))(
                Wh, s, ok), gate)(Wh, slopes[d], ok) for d in range(lay.dim)]
            U_new = staged(lambda U, F, Wh: jax.vmap(lambda u, f, w: flux_update(u, f, dt, scheme, w)[0])(U, F, Wh),
                           gate)(U0, fluxes, Wh)
            return (U_new, staged(cfl_dt, gate)(U_new), fluxes), ok

        def allowed_after(ok, U_new):
            return staged(lambda ok, U_new: self._second_order_allowed(ok, U_new, H, level, ids, fluid), gate)(
                ok, U_new)

        def floored(U):
            U, cells, mass, energy = vacuum_floored(U, gamma, fluid)
            volume = float(np.prod(scheme.dx))
            return U, cfl_dt(U), cells, jnp.sum(mass) * volume, jnp.sum(energy) * volume

        first = jnp.ones((cap,) + tuple(n + 2 for n in lay.block_shape), bool)
        (U_new, dt_next, fluxes), added = with_fallbacks(attempt, allowed_after, staged(floored, gate), first,
                                                         self.RETRIES)
        H = self._advanced(H, level, ids, U0, U_new, fluxes, dt)
        forces = self._side_forces(H, level, ids, valid, fluxes)
        H = H._replace(floors=H.floors + added, updates=H.updates + count * np.prod(lay.block_shape))
        return H, dt_next, forces

    def _second_order_allowed(self, ok, U_new, H, level, ids, fluid):
        """``ok`` (each block and one ghost layer) without the cells at or
        next to a cell whose new state is not physical, in this block or a
        neighbour (as :func:`~partmesh.gridref.euler.step.second_order_allowed`
        on a whole grid: no cell beyond a side of the domain counts)."""
        W = primitive(U_new, self.gamma)
        bad = (~(W[0] > 0.0) | ~(W[-1] > 0.0)) & fluid
        lay = self.layout
        stored = jnp.zeros((lay.n_blocks(level), *lay.block_shape), bool).at[ids].set(bad, mode="drop")
        src = sources(lay, level, block_origins(lay, level, ids, -2), lay.block + 4)
        around = stored.ravel()[src.index] & ~src.outside
        grown = jax.vmap(_dilated)(around)
        inner = (slice(None),) + (slice(1, -1),) * lay.dim
        return ok & ~grown[inner]

    def _advanced(self, H, level, ids, U0, U_new, fluxes, dt):
        """``H`` with the level's blocks set to ``U_new``; for a level with a
        finer one, its old state and Δt F kept; for one with a coarser one,
        Δt F through its blocks' boundary faces added to its register."""
        levels, L = self.levels, self.layout.levels
        U = levels.with_blocks(H.U[level], ids, U_new)
        H = H._replace(U=_set(H.U, level, U))
        if level < L - 1:
            H = H._replace(old=_set(H.old, level, levels.with_blocks(H.old[level], ids, U0)),
                           flux=_set(H.flux, level, tuple(levels.with_blocks(H.flux[level][d], ids,
                                                                             [dt * f for f in F])
                                                          for d, F in enumerate(fluxes))))
        if level > 0:
            register = tuple(tuple(r + dt * _boundary_faces(f, d, self.layout.dim) for r, f in zip(reg, F))
                             for d, (reg, F) in enumerate(zip(H.register[level], fluxes)))
            H = H._replace(register=_set(H.register, level, register))
        return H

    def _side_forces(self, H, level, ids, valid, fluxes):
        """The normal momentum flux through the level's faces on every side
        of the domain (x_lo, x_hi[, y_lo, y_hi]) that no finer level covers,
        times their area (per metre depth in 2D, per square metre in 1D)."""
        lay = self.layout
        nb = lay.blocks(level)
        coords = coords_of(ids, nb, jnp)
        open_ = jnp.broadcast_to(valid.reshape((-1,) + (1,) * lay.dim), valid.shape + lay.block_shape)
        if level < lay.levels - 1:
            open_ = open_ & ~_covered(H.maps[level + 1], ids, lay, level)
        dx = lay.spacing(level)
        forces = []
        for d in range(lay.dim):
            momentum = _boundary_faces(fluxes[d][1 + d], d, lay.dim)  # (n, 2[, B])
            edge = _boundary_cells(open_, d, lay.dim)
            area = 1.0 if lay.dim == 1 else dx[1 - d]
            for side, at_side in ((0, coords[d] == 0), (1, coords[d] == nb[d] - 1)):
                m = momentum[:, side]
                mask = edge[:, side] & at_side.reshape((-1,) + (1,) * (m.ndim - 1))
                forces.append(jnp.sum(jnp.where(mask, m, 0.0)) * area)
        return jnp.stack(forces)


def _set(levels: tuple, level: int, value) -> tuple:
    return levels[:level] + (value,) + levels[level + 1:]


def _boundary_faces(F, d: int, dim: int):
    """A batch of blocks' fluxes through their two boundary faces normal to
    axis ``d``: (n, 2[, B]) from (n, B + 1) or (n, B[, B + 1]) / (n, B + 1, B)."""
    if dim == 1:
        return jnp.stack([F[:, 0], F[:, -1]], axis=1)
    if d == 0:
        return jnp.stack([F[:, :, 0], F[:, :, -1]], axis=1)
    return jnp.stack([F[:, 0, :], F[:, -1, :]], axis=1)


def _boundary_cells(mask, d: int, dim: int):
    """A batch of blocks' cell masks at their two boundary rows normal to
    axis ``d``: (n, 2[, B])."""
    return _boundary_faces(mask, d, dim)


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
    kids = flat[cy * nb_f[0] + cx]  # (n, 2, 2)
    return jnp.repeat(jnp.repeat(kids, half, axis=1), half, axis=2)

