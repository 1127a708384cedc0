"""Time subcycling over the levels of a hierarchy (Berger & Colella 1989,
§3): one step of level 0 is a step of every level ``l`` of size
``Δt / 2ˡ``, the finer levels stepping twice for each step of the coarser
one, their halo filled before each step from the coarser level
interpolated in time, then restricted onto it and refluxed. The recursion
runs over the levels in Python (static) and over the two sub-steps in a
``jax.lax.fori_loop``, so every level's step is compiled once.

The records of the finest steps (``2^(L−1)`` a step of level 0) are kept:
the probes, from the finest level whose active blocks hold a probe's
stencil at the record's time (a coarser level's state interpolated in
time between its step's two ends), and the side forces, every level's
force over its step under way.
"""

from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.gridref.amr.hierarchy import Hierarchy, Levels, from_level, joined, with_level
from partmesh.gridref.grid import Grid, bilinear_stencil


class Subcycler:
    """``advance(H, t, dt) -> (H, dt_next, probes, forces)``: a step ``dt``
    of level 0 and the steps of every finer level inside it.

    ``level_step(H, level, dt, imposed) -> (H, dt_next, forces)`` advances
    one level (:class:`partmesh.gridref.euler.blocks.LevelStepper`);
    ``imposed(t)``: the conservative state of every side at time ``t`` (for
    inflow sides); ``probe(H, theta) -> (n_probes,)``: the probes, each level
    ``l``'s state taken at ``(1 − θ_l) old + θ_l U``; ``dt_next`` is the
    largest step of level 0 every level allows, min over l of 2ˡ times its
    own CFL step."""

    def __init__(self, levels: Levels, level_step: Callable, imposed: Callable, probe: Callable, n_probes: int,
                 n_forces: int):
        self.levels, self.level_step, self.imposed, self.probe = levels, level_step, imposed, probe
        self.n_probes, self.n_forces = n_probes, n_forces
        self.L = levels.layout.levels

    @property
    def records(self) -> int:
        """Records per step of level 0: one per finest step."""
        return 1 << (self.L - 1)

    def advance(self, H: Hierarchy, t, dt):
        records = (jnp.zeros((self.records, self.n_probes)), jnp.zeros((self.records, self.n_forces)))
        dt_next = jnp.full(self.L, jnp.inf)
        H, records, _, dt_next = self._go(0, H, t, dt, (), (), records, jnp.zeros((), jnp.int32), dt_next)
        scale = jnp.asarray([float(1 << level) for level in range(self.L)])
        probes, forces = records if self.L > 1 else (records[0][0], records[1][0])  # (one level: one record, no axis)
        return H, jnp.min(dt_next * scale), probes, forces

    def _go(self, level, H, t, dt, clocks, forces, records, n, dt_next):
        H, dt_level, force = self.level_step(H, level, dt, self.imposed(t))
        dt_next = dt_next.at[level].set(dt_level)
        clocks, forces = clocks + ((t, dt),), forces + (force,)
        if level == self.L - 1:
            end = t + dt
            theta = jnp.stack([jnp.where(k == level, 1.0, (end - c[0]) / c[1]) for k, c in enumerate(clocks)])
            probes, sides = records
            records = (probes.at[n].set(self.probe(H, theta)), sides.at[n].set(sum(forces)))
            return H, records, n + 1, dt_next
        fine = level + 1
        H = H._replace(register=with_level(H.register, fine, jax.tree_util.tree_map(jnp.zeros_like, H.register[fine])))
        half = 0.5 * dt

        def substep(k, carry):
            part, records, n, dt_next = carry
            t_k = t + k * half
            H_k = self.levels.halo_filled(joined(H, part, fine), fine, 0.5 * k, self.imposed(t_k))
            H_k, records, n, dt_next = self._go(fine, H_k, t_k, half, clocks, forces, records, n, dt_next)
            return from_level(H_k, fine), records, n, dt_next

        # (the coarser levels, which the finer steps only read, stay outside the loop's carry)
        part, records, n, dt_next = jax.lax.fori_loop(0, 2, substep, (from_level(H, fine), records, n, dt_next))
        H = joined(H, part, fine)
        ids, count = H.active[fine]
        levels = self.levels
        U = levels.restricted_into(H.U[level], H.U[fine], fine, ids, count)
        U = levels.refluxed(U, H.flux[level], H.register[fine], H.maps[fine], fine, ids, count)
        return H._replace(U=with_level(H.U, level, U)), records, n, dt_next


def probe_stencils(levels: Levels, points) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Per level, the (bi)linear stencil of every probe ``points`` (n, dim):
    flat storage indices (n, 2^dim), weights (n, 2^dim) and the flat ids of
    the blocks holding them (n, 2^dim); points beyond the outermost cell
    centres take the edge values (as on a uniform grid)."""
    lay = levels.layout
    out = []
    for level in range(lay.levels):
        cells, h = lay.cells(level), lay.spacing(level)
        grid = Grid(cells, tuple((o, o + n * s) for o, n, s in zip(lay.origin, cells, h)))
        index, weights = bilinear_stencil(grid, points, lay.periodic)
        at = (index,) if lay.dim == 1 else np.divmod(index, cells[0])[::-1]
        index = lay.cell_index(level, at)
        out.append((index, weights, index // lay.block ** lay.dim))
    return out
