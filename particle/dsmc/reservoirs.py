"""The gas beyond the open sides of a DSMC run (SPEC §3.3): slabs of
equilibrium particles outside every open side that supply the particles
flying in over a step — an inflow's imposed state, or at an outflow the
characteristic far-field state (:func:`~partmesh.particle.dsmc.far_field.far_field_state`)
between the cells next to the side and the undisturbed gas. The molecules
that enter across a boundary from an equilibrium stream are those of the
stream beyond it that reach it within the step (Bird 1994, "Molecular Gas
Dynamics and the Direct Simulation of Gas Flows", ch. 4, the flux across a
surface); drawing the slab and flying it with the rest counts them exactly."""

from __future__ import annotations

import numpy as np

from partmesh.cases.scene import Inflow
from partmesh.particle.dsmc.far_field import far_field_state
from partmesh.particle.dsmc.gas import particles_in_cells
from partmesh.particle.dsmc.sample import moment_state
from partmesh.particle.dsmc.walls import inside_obstacles

#: an open side's reservoir is deep enough for inward normal speeds up to U_n + RESERVOIR_SIGMAS √θ
RESERVOIR_SIGMAS = 6.0
#: steps over which an outflow's boundary state is averaged (exponentially)
OUTFLOW_MEMORY = 20.0


def boundary_layer(side, dim):
    """Index of the cells next to ``side`` in a (nx,), (ny, nx) or (nz, ny, nx) array."""
    axis, upper = side // 2, side % 2 == 1
    if dim == 1:
        return -1 if upper else 0
    index = [slice(None)] * dim
    index[dim - 1 - axis] = -1 if upper else 0
    return tuple(index)


class Reservoirs:
    """The reservoirs beyond the open sides of one run on a cell grid from
    ``lo`` to ``hi`` whose initial state per cell is ``initial_fields``
    (rho, u, v, w, p): particles of ``mass`` with ``zeta`` internal degrees,
    drawn from ``seed``; densities and pressures scaled by ``fill`` (a ring
    cell's, in r–z); none put inside the obstacle ``polygons``.

    ``running`` holds, per outflow side, the running moments of the cells
    next to it (a checkpoint keeps them)."""

    def __init__(self, scene, lo, hi, initial_fields, mass, zeta, seed, fill=1.0, polygons=None):
        self.scene, self.lo, self.hi = scene, lo, hi
        self.initial_fields, self.mass, self.zeta, self.seed, self.fill = initial_fields, mass, zeta, seed, fill
        self.polygons = polygons if scene.obstacles else None
        self.ncell = int(initial_fields[0].size)
        self.running = {}

    def particles(self, side, t, dt, n, cells):
        """``(x, v, e)`` of the equilibrium particles in a slab outside the
        open ``side``, deep enough to hold every particle that can fly in
        over ``dt`` up to ``t`` (step number ``n``), at the state
        :meth:`outside_state` gives from the step's cell sums ``cells``.
        Random streams: the redraw of cell c at step n draws from key c, the
        initial fill of cell c from step 0, key ncell + c, the reservoir of
        side s at step n from key 2 ncell + s."""
        dim = self.scene.dim
        axis, upper = side // 2, side % 2 == 1
        rho, *velocity, p = self.outside_state(side, t, cells)
        normal_in = -velocity[axis] if upper else velocity[axis]
        depth = dt * (normal_in + RESERVOIR_SIGMAS * np.sqrt(p / rho))
        if depth <= 0.0:
            return np.zeros((0, dim)), np.zeros((0, 3)), np.zeros(0)
        corner, size = self.lo.copy(), self.hi - self.lo
        corner[axis], size[axis] = (self.hi[axis] if upper else self.lo[axis] - depth), depth
        x, vel, e = particles_in_cells(corner, size, np.ones(dim, dtype=np.int64),
                                       *(np.array([q], dtype=float) for q in (rho * self.fill, *velocity,
                                                                              p * self.fill)),
                                       self.mass, self.zeta, self.seed, n, 2 * self.ncell + side)
        if self.polygons is not None:  # an obstacle may run out through the side: no gas inside it
            fluid = ~inside_obstacles(x, *self.polygons)
            x, vel, e = x[fluid], vel[fluid], e[fluid]
        return x, vel, e

    def outside_state(self, side, t, cells):
        """(rho, u, v, w, p) of the gas beyond an open side: an inflow's imposed
        state (w = 0); at an outflow, the characteristic far-field state between
        the layer of cells next to the side and the scene's initial state
        there, the undisturbed gas. The layer's state comes from its moments
        in ``cells`` averaged over the last ~``OUTFLOW_MEMORY`` steps:
        copying a single step's sample out into the reservoir would feed its
        scatter back in, and the boundary state would drift like a random
        walk. Flow along axes the scene does not resolve is only scatter:
        its velocity is 0 and its energy thermal."""
        boundary = self.scene.boundaries[self.scene.sides[side]]
        if isinstance(boundary, Inflow):
            rho, u, v, p = (float(q) for q in boundary.state(t))
            return rho, u, v, 0.0, p
        sums = self._layer_sums(side, cells)
        running = self.running.get(side, sums)
        running = self.running[side] = running + (sums - running) / OUTFLOW_MEMORY
        layer = boundary_layer(side, self.scene.dim)
        far = tuple(float(np.mean(q[layer])) for q in self.initial_fields)
        inside = self._layer_state(running) if running[0] > 0.0 else far
        return far_field_state(inside, far, side // 2, 1.0 if side % 2 else -1.0, self.scene.gamma)

    def _layer_sums(self, side, cells) -> np.ndarray:
        """(S0, S1 (3), S2, open volume) of the layer of cells next to ``side``."""
        layer = boundary_layer(side, self.scene.dim)
        shape = self.initial_fields[0].shape
        return np.array([cells.s0.reshape(shape)[layer].sum(),
                         *(cells.s1[:, a].reshape(shape)[layer].sum() for a in range(3)),
                         cells.s2.reshape(shape)[layer].sum(), cells.volume.reshape(shape)[layer].sum()])

    def _layer_state(self, sums):
        """(rho, u, v, w, p) from a layer's moments (:meth:`_layer_sums`); the
        velocity along an unresolved axis is 0."""
        rho, U, p, _ = moment_state(sums[0:1], sums[None, 1:4], sums[4:5], sums[5:6], 1, self.mass,
                                    self.scene.gamma, self.scene.dim)
        velocity = (float(U[0, a]) if a < self.scene.dim else 0.0 for a in range(3))
        return float(rho[0]), *velocity, float(p[0])
