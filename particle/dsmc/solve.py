"""Equilibrium DSMC (method ``dsmc``): run a scene, return a schema Dataset
on the scene's output grid (Pullin 1980, J. Comput. Phys. 34, 231; SPEC §3.3).

Each step: the particles fly freely for Δt (specular reflection at
reflecting sides, wrap on periodic axes, removal through open sides);
reservoirs of equilibrium gas outside every open side — the imposed state at
an inflow, the state of the adjacent cells at an outflow — put in the
particles that fly in over the step (:mod:`partmesh.particle.dsmc.reservoirs`);
the particles are sorted into cells of size ``dx`` and every cell with two
or more is redrawn from its local equilibrium, conserving its momentum and
energy exactly (:mod:`partmesh.particle.dsmc.equilibrate`), about the
cell's mean velocity and temperature or, with ``profile="linear"``, about
their limited linear profiles across the cell
(:mod:`partmesh.particle.dsmc.profile`). Δt = C Δx / (max|U| + 3 √θ_max)
over the cells, C = ``cfl``; with ``redraw="local"`` a cell is redrawn
only at its own Courant step, a multiple of Δt
(:mod:`partmesh.particle.dsmc.intervals`).

With ``collisions="larsen-borgnakke"`` the redraw gives way to true binary
collisions (:mod:`partmesh.particle.dsmc.collide`: no-time-counter selection, VHS
molecules with exponent ``omega``, Larsen–Borgnakke rotational exchange
with collision number ``z_rot``) at the ``mean_free_path`` of the scene's
lowest initial density: a non-equilibrium gas for comparison, which tends
to the equilibrium mode as the mean free path shrinks below the cell.

Obstacles are the scene's shapes as convex polygons, reflecting specularly
(:mod:`partmesh.particle.dsmc.walls`); a cell's density counts only the part of it
open to the gas. Particles stand for equal masses: ``ppc`` particles per
cell in the lowest-density initial state. Output fields are the cumulative
moments of the last ``window`` steps before each output time.

In an axisymmetric scene the particles fly in 3D and are rotated back into
the r–z plane, and carry radial weights that the redraw resamples to an
even count per ring cell (:mod:`partmesh.particle.dsmc.axisymmetric`);
``ppc`` is then the count per cell of the lowest initial density.
"""

from __future__ import annotations

from functools import reduce

import numba
import numpy as np

from partmesh.cases.checkpoint import checkpoint_for
from partmesh.cases.compiling import compiling
from partmesh.cases.errors import InputError
from partmesh.cases.history import History, Output, RunRecord
from partmesh.cases.march import landed
from partmesh.cases.shape_factories import square
from partmesh.particle.dsmc.axisymmetric import fill_factor, radial_flight, resampled_redraw, ring_weights
from partmesh.particle.dsmc.cells import UNWEIGHTED, cell_index, particle_buffers, sort_into_cells, with_room
from partmesh.particle.dsmc.collide import collide
from partmesh.particle.dsmc.equilibrate import equilibrate
from partmesh.particle.dsmc.gas import internal_degrees, particles_in_cells
from partmesh.particle.dsmc.intervals import EVERY_CELL, due_cells, signal_speeds
from partmesh.particle.dsmc.method import DSMCSettings
from partmesh.particle.dsmc.move import OPEN, PERIODIC, REFLECT, free_flight
from partmesh.particle.dsmc.profile import NO_SLOPES, cell_means, limited_slopes
from partmesh.particle.dsmc.reservoirs import Reservoirs, boundary_layer
from partmesh.particle.dsmc.sample import CellSums, probe_cells, probe_pressures, unbiased_pressure
from partmesh.particle.dsmc.walls import (
    fluid_fraction,
    fly_past_obstacles,
    inside_obstacles,
    obstacle_polygons,
    push_out_of_obstacles,
)
from partmesh.particle.march import march_particles

#: true collisions refuse a mean free path that makes a particle collide more often per step (the continuum limit,
#: which the equilibrium redraw computes directly)
MAX_COLLISIONS_PER_STEP = 100.0
#: an obstacle on which the kernels are compiled
_UNIT_SQUARE = square(2.0, 2.0, 1.0)


def solve(scene, settings: DSMCSettings):
    """Run ``scene`` with equilibrium DSMC and checked ``settings``
    (:class:`~partmesh.particle.dsmc.method.DSMCSettings`). Raises
    :class:`~partmesh.cases.errors.SolverFailed` with the partial result if the run
    is interrupted; checkpoints as in the other methods
    (:mod:`partmesh.cases.checkpoint`; a resumed run is bit for bit an uninterrupted
    one)."""
    zeta = internal_degrees(scene.gamma)
    with compiling("dsmc", settings.progress) as compiled:
        _compile_kernels(scene.dim, zeta, settings.collisions, scene.geometry == "axisymmetric")
    compile_seconds = compiled.seconds
    gas = _Gas(scene, settings.dx, settings.ppc, zeta, settings.seed, settings.profile, settings.redraw, settings.cfl)
    if settings.collisions == "larsen-borgnakke":
        gas.collide_with(settings.mean_free_path, settings.omega, settings.z_rot, settings.cfl)
    run = _Run(scene, gas, settings.record(), compile_seconds)
    cfl, window = settings.cfl, settings.window
    t = scene.t_start
    ckpt = checkpoint_for(scene, settings)
    saved = ckpt.saved_state(run)
    if saved is not None:
        t = saved["t"]
        gas.restore(saved["gas"])

    def step(gas, t, dt_cfl, t_out):
        dt_stable = cfl * gas.dx / gas.signal_speed()
        dt = landing_step(dt_stable, t_out - t)
        forces = gas.step(t, dt, run.n_steps)
        t_new = landed(t, dt, t_out)
        if t_out - t_new <= (window - 1) * dt * (1 + 1e-9) or t_new == t_out:
            gas.sample_into(run.sums)
        return gas, dt, dt_stable, (run.probes(), forces)

    def saved_state(gas, t, dt_cfl):
        return {"t": t, "gas": gas.saved()}

    return march_particles(run, gas, t, step, ckpt, saved_state, settings, gas.x.shape[0])


def landing_step(dt_max: float, left: float) -> float:
    """The next step toward an output time ``left`` seconds away, given the
    stable step ``dt_max``: all of ``left`` if it fits in one step, half of
    it if it fits in two, else ``dt_max`` — so an interval between output
    times ends in two even steps, never in a sliver.

    A sliver matters to DSMC: the force on a wall is the momentum the
    particles deliver over the step divided by the step, whose scatter grows
    as 1/√dt (a step a thousandth of the others put a 93 kN/m spike on a
    20 kN/m wall force), and every step adds one equilibrium redraw."""
    if left <= dt_max:
        return left
    return 0.5 * left if left < 2.0 * dt_max else dt_max


def _compile_kernels(dim, zeta, collisions, radial=False):
    """Compile (or load from the cache) the numba kernels of a step, on two
    particles, so that the run's time excludes it."""
    x, v, e = np.full((2, dim), 0.5), np.zeros((2, 3)), np.zeros(2)
    lo, spacing, shape = np.zeros(dim), np.ones(dim), np.ones(dim, dtype=np.int64)
    free_flight(x, v, 0.0, lo, spacing, np.full(2 * dim, REFLECT, dtype=np.int64))
    start = sort_into_cells(x, v, e, UNWEIGHTED, np.ones(2, dtype=np.bool_), lo, spacing, shape, 1, x.copy(), v.copy(),
                            e.copy(), UNWEIGHTED)
    equilibrate(x, v, e, start, zeta, 0, 0, np.zeros(1), np.zeros((1, 3)), np.zeros(1), NO_SLOPES, EVERY_CELL)
    cell_means(v, e, UNWEIGHTED, start, zeta)
    if radial:
        w, sides = np.ones(2), np.full(2, REFLECT, dtype=np.int64)
        radial_flight(x, v, w, 0.0, 1.0, REFLECT)
        free_flight(x[:, 1:], v[:, 1:], 0.0, lo[1:], spacing[1:], sides, w)
        resampled_redraw(x, v, e, w, start, np.ones(1), zeta, 0, 0, np.zeros(1), np.zeros((1, 3)), np.zeros(1))
        cell_means(v, e, w, start, zeta)
    if collisions == "larsen-borgnakke":
        collide(v, e, start, np.ones(1), 1.0, 1.0, 1.0, 0.74, 5.0, zeta, 0, 0, np.ones(1), np.zeros(1),
                np.zeros((1, 3)), np.zeros(1))
    cell_index(x, lo, spacing, shape)
    one = np.ones(1)
    particles_in_cells(lo, spacing, shape, one, 0.0 * one, 0.0 * one, 0.0 * one, one, 1.0, zeta, 0, 0, 0)
    if dim == 2:
        polygons = obstacle_polygons([_UNIT_SQUARE], 1.0)
        fly_past_obstacles(x, v, 0.0, *polygons)
        push_out_of_obstacles(x, v, *polygons)


class _Gas:
    """The particles of one run and the step that advances them."""

    def __init__(self, scene, dx, ppc, zeta, seed, profile="uniform", redraw="every-step", cfl=1.0):
        self.scene, self.zeta, self.seed, self.profile = scene, zeta, seed, profile
        dim = scene.dim
        self.lo = np.array([lo for lo, _ in scene.domain])
        self.hi = np.array([hi for _, hi in scene.domain])
        self.shape = tuple(max(1, int(round((hi - lo) / dx))) for lo, hi in scene.domain)
        self.spacing = (self.hi - self.lo) / np.array(self.shape)
        self.dx = float(self.spacing.min())
        self.sides = np.array([_side_kind(scene.boundaries[s]) for s in scene.sides], dtype=np.int64)
        centres = [self.lo[a] + (np.arange(self.shape[a]) + 0.5) * self.spacing[a] for a in range(dim)]
        grid = centres if dim == 1 else np.meshgrid(*centres[::-1], indexing="ij")[::-1]  # ([z,] y, x) layout
        given = scene.initial(grid[0], grid[1] if dim > 1 else None, self.dx, *grid[2:])
        rho, u, v, *w, p = (np.broadcast_to(np.asarray(q, float), grid[0].shape) for q in given)
        v = v if dim > 1 else np.zeros_like(u)
        w = w[0] if dim == 3 else np.zeros_like(u)
        #: ring cells and weighted particles (:mod:`partmesh.particle.dsmc.axisymmetric`)
        self.radial = scene.geometry == "axisymmetric"
        self.fill = fill_factor(self.spacing[0]) if self.radial else 1.0
        self.mass = float(rho.min()) * self.fill * float(np.prod(self.spacing)) / ppc
        self.initial_fields = (rho, u, v, w, p)  # the scene's initial state per cell: far field of an outflow
        self.ncell = int(np.prod(self.shape))
        #: under ``redraw="local"``, the flight time since each cell's last redraw and the reach C Δx of a
        #: redraw interval (:mod:`partmesh.particle.dsmc.intervals`); None: every cell every step
        self.hold = np.zeros(self.ncell) if redraw == "local" else None
        self.reach = cfl * self.dx
        flat = [np.array(q, dtype=float).reshape(-1) for q in (rho, u, v, w, p)]  # (writable: one kernel signature)
        if self.radial:
            flat[0], flat[-1] = flat[0] * self.fill, flat[-1] * self.fill
        self.x, self.v, self.e = particles_in_cells(self.lo, self.spacing, np.array(self.shape, dtype=np.int64),
                                                    *flat, self.mass, zeta, seed, 0, self.ncell)
        #: the particles' radial weights (None in a planar scene)
        self.w = ring_weights(self.x[:, 0], self.spacing[0]) if self.radial else None
        #: the weight a ring cell's particles are resampled to (:func:`resampled_redraw`)
        self.target = (np.tile(ring_weights(centres[0], self.spacing[0]), self.ncell // self.shape[0])
                       if self.radial else None)
        self.polygons = obstacle_polygons(scene.obstacles, self.dx) if dim == 2 else None
        self.reservoirs = Reservoirs(scene, self.lo, self.hi, self.initial_fields, self.mass, zeta, seed, self.fill,
                                     self.polygons)
        self.safeguard, self.bounces = 0, 0
        self.vhs = None  # (F_N σ_ref, g_ref, ω, Z_rot) under true collisions
        self.sigma_g_max = None  # their (F_N σg)_max per cell
        self.collisions = 0
        self._spare = None  # buffers the next cell sort writes into
        fraction = None
        if scene.obstacles:
            fluid = ~inside_obstacles(self.x, *self.polygons)
            self.x, self.v, self.e = self.x[fluid], self.v[fluid], self.e[fluid]
            fraction = fluid_fraction(*self.polygons, self.lo, self.spacing, self.shape)
        out = scene.output
        self.output_fraction = None if not scene.obstacles else fluid_fraction(
            *self.polygons, np.array([lo for lo, _ in out.domain]), np.asarray(out.spacing), out.shape)
        self.cells = CellSums(self.lo, self.spacing, self.shape, fraction, self.radial)
        self.cells.add(self.x, self.v, self.e, self.w)
        self.state = self.cells.state(self.mass, scene.gamma)

    def saved(self) -> dict:
        """Everything the next steps depend on, for a checkpoint: the
        particles in their memory order, the last cell sums (their state follows from them), an
        outflow's running boundary moments, the collision maxima, the
        counters."""
        return {"x": self.x, "v": self.v, "e": self.e, "w": self.w, "cells": self.cells,
                "outflow": self.reservoirs.running, "sigma_g_max": self.sigma_g_max,
                "counters": (self.safeguard, self.bounces, self.collisions), "hold": self.hold}

    def restore(self, saved: dict) -> None:
        """Continue from :meth:`saved`."""
        self.x, self.v, self.e, self.w = saved["x"], saved["v"], saved["e"], saved.get("w")  # (none: planar)
        self.cells, self.reservoirs.running = saved["cells"], saved["outflow"]
        if not hasattr(self.cells, "count"):  # (a checkpoint written before the cells counted their particles)
            self.cells.count = np.bincount(cell_index(self.x, self.lo, self.spacing, self.cells.shape_array),
                                           minlength=self.ncell)
        self.state = self.cells.state(self.mass, self.scene.gamma)  # (what the last step computed from them)
        self.sigma_g_max = saved["sigma_g_max"]
        self.safeguard, self.bounces, self.collisions = saved["counters"]
        self.hold = saved.get("hold", self.hold)  # (none: a checkpoint from before local redraw intervals)
        self._spare = None

    def collide_with(self, mean_free_path, omega, z_rot, cfl):
        """Switch the step from the equilibrium redraw to VHS /
        Larsen–Borgnakke collisions (:mod:`partmesh.particle.dsmc.collide`) with
        ``mean_free_path`` at the lowest initial density ρ_ref, θ_ref there:
        F_N σ_ref = m/(√2 ρ_ref λ_ref) at g_ref = 4 √(θ_ref/π). Refuses a
        mean free path that makes a particle of the densest initial cell
        collide more than MAX_COLLISIONS_PER_STEP times in a step."""
        rho, *_, p = (q.reshape(-1) for q in self.initial_fields)
        ref = int(np.argmin(rho))
        g_ref = 4.0 * np.sqrt(p[ref] / rho[ref] / np.pi)
        sigma = self.mass / (np.sqrt(2.0) * rho[ref] * mean_free_path)
        def sigma_g(g):  # F_N σ(g) g of VHS molecules
            return sigma * g * (g / g_ref) ** (1.0 - 2.0 * omega)

        # collisions per particle per step, n σ(g) ⟨g⟩ Δt, at the initial state of every cell
        g_mean = 4.0 * np.sqrt(p / rho / np.pi)
        rate = rho / self.mass * sigma_g(g_mean)
        per_step = float(np.max(rate)) * cfl * self.dx / self.signal_speed()
        if per_step > MAX_COLLISIONS_PER_STEP:
            shortest = mean_free_path * per_step / MAX_COLLISIONS_PER_STEP
            raise InputError(f"mean_free_path = {mean_free_path:g} m makes a particle collide ~{per_step:.0f} times "
                             f"per step on cells of {self.dx:g} m (at most {MAX_COLLISIONS_PER_STEP:g}): the gas is "
                             f"in the continuum limit that collisions='equilibrium' computes; use "
                             f"mean_free_path >= {shortest:.3g} m.")
        self.vhs = (float(sigma), float(g_ref), float(omega), float(z_rot))
        # (F_N σg)_max per cell starts at twice the mean relative speed of the densest initial state, then adapts
        self.sigma_g_max = np.full(self.ncell, float(np.max(sigma_g(2.0 * g_mean))))

    def totals(self) -> tuple[float, float]:
        """Mass and energy (translational and internal) of all particles."""
        if self.radial:
            heat = 0.5 * np.einsum("ij,ij->i", self.v, self.v) + self.e
            return self.mass * float(self.w.sum()), self.mass * float(np.dot(self.w, heat))
        energy = 0.5 * np.einsum("ij,ij->", self.v, self.v) + self.e.sum()
        return self.mass * self.x.shape[0], self.mass * float(energy)

    def in_solids(self) -> int:
        """Particles inside an obstacle polygon (the solver keeps this 0)."""
        return int(inside_obstacles(self.x, *self.polygons).sum()) if self.scene.obstacles else 0

    def signal_speed(self) -> float:
        """max |U| + 3 √θ over the cells of the last sort (θ = p/ρ)."""
        state = self.state
        filled = (self.cells.s0 > 0) & (self.cells.volume > 0)  # (a sliver of a cut cell may count as solid)
        flow = reduce(np.hypot, (state.u, state.v, state.w)[: max(2, self.scene.dim)])  # (|(u, v)| in 1D as in 2D)
        speed = flow.reshape(-1)[filled] + 3.0 * np.sqrt(state.p / state.rho).reshape(-1)[filled]
        return float(speed.max())

    def step(self, t, dt, n) -> np.ndarray:
        """Advance the gas by ``dt`` from ``t`` (step number ``n``); returns
        the force on every side over the step (per metre depth in 2D, per
        square metre in 1D)."""
        entering = [self.reservoirs.particles(side, t + dt, dt, n, self.cells) for side in range(len(self.sides))
                    if self.sides[side] == OPEN]
        if entering:
            self.x, self.v, self.e = (appended(a, [part[k] for part in entering])
                                      for k, a in enumerate((self.x, self.v, self.e)))
            if self.radial:
                self.w = appended(self.w, [ring_weights(part[0][:, 0], self.spacing[0]) for part in entering])
        if self.radial:
            gone, delivered = self._radial_flight(dt)
        elif self.scene.obstacles:
            # obstacles first, then the domain's sides fold the end points back (a flight of 0 s)
            self.bounces += fly_past_obstacles(self.x, self.v, dt, *self.polygons)
            gone, delivered = free_flight(self.x, self.v, 0.0, self.lo, self.hi, self.sides)
            self.safeguard += push_out_of_obstacles(self.x, self.v, *self.polygons)
        else:
            gone, delivered = free_flight(self.x, self.v, dt, self.lo, self.hi, self.sides)
        # the redraw conserves each cell's sums: they are the step's sample
        self.cells.reset()
        if self.radial:
            start = self._resampled(~gone, n, dt)
        else:
            start = self._sort(~gone)
            if self.vhs is None:
                equilibrate(self.x, self.v, self.e, start, self.zeta, self.seed, n, self.cells.s0, self.cells.s1,
                            self.cells.s2, *self._redraw_plan(start, UNWEIGHTED, dt))
            else:
                self.collisions += collide(self.v, self.e, start, self.cells.volume, dt, *self.vhs, self.zeta,
                                           self.seed, n, self.sigma_g_max, self.cells.s0, self.cells.s1, self.cells.s2)
        self.cells.samples, self.cells.count = 1, np.diff(start)
        self.state = self.cells.state(self.mass, self.scene.gamma)
        return self._side_forces(delivered, dt)

    def _radial_flight(self, dt):
        """The flight of weighted particles in r–z (:mod:`partmesh.particle.dsmc.axisymmetric`):
        ``(gone, delivered)`` as :func:`free_flight`'s (none to the axis)."""
        gone, outer = radial_flight(self.x, self.v, self.w, dt, self.hi[0], self.sides[1])
        gone_z, along = free_flight(self.x[:, 1:], self.v[:, 1:], dt, self.lo[1:], self.hi[1:], self.sides[2:],
                                    self.w)
        return gone | gone_z, np.array([0.0, outer, *along])

    def _resampled(self, keep, n, dt) -> np.ndarray:
        """The particles flagged in ``keep`` in a stable cell order, resampled
        and redrawn (:func:`resampled_redraw`) into the step's cell sums;
        returns the cell starts of the sort."""
        start = self._sort(keep)
        sorted_buffers = tuple(_buffer_of(a) for a in (self.x, self.v, self.e, self.w))
        slopes, due = self._redraw_plan(start, self.w, dt)
        self.x, self.v, self.e, self.w, _ = resampled_redraw(self.x, self.v, self.e, self.w, start, self.target,
                                                             self.zeta, self.seed, n, self.cells.s0, self.cells.s1,
                                                             self.cells.s2, out=self._spare, slopes=slopes, due=due)
        self._spare = sorted_buffers
        return start

    def _redraw_plan(self, start, weights, dt) -> tuple:
        """``(slopes, due)`` of the redraw after a flight of ``dt``, for the
        particles in cell order: the slopes of the mean velocity and
        temperature it draws about (:func:`limited_slopes`; :data:`NO_SLOPES`
        under ``profile="uniform"``) and the cells it redraws
        (:func:`due_cells`; :data:`EVERY_CELL` under ``redraw="every-step"``),
        both from one pass of :func:`cell_means`."""
        if self.profile == "uniform" and self.hold is None:
            return NO_SLOPES, EVERY_CELL
        count, mean = cell_means(self.v, self.e, weights, start, self.zeta)
        slopes = (NO_SLOPES if self.profile == "uniform" else
                  limited_slopes(count, mean, self.shape, self.spacing, self.scene.periodic))
        due = (EVERY_CELL if self.hold is None else
               due_cells(self.hold, dt, signal_speeds(mean, self.scene.dim), self.reach))
        return slopes, due

    def _sort(self, keep) -> np.ndarray:
        """Put the particles flagged in ``keep`` (and their weights, in r–z)
        in cell order (into the spare buffers, which then hold the old
        order) and drop the rest; returns the cell starts."""
        n = self.x.shape[0]
        if self._spare is None or min(b.shape[0] for b in self._spare[:3]) < n:
            self._spare = particle_buffers(n, self.scene.dim, self.radial)
        weights = self.w if self.radial else UNWEIGHTED
        old = tuple(_buffer_of(a) for a in (self.x, self.v, self.e, weights))
        start = sort_into_cells(*(a[:n] for a in old), keep, self.lo, self.spacing, self.cells.shape_array,
                                numba.get_num_threads(), *self._spare)
        self.x, self.v, self.e = (buffer[:start[-1]] for buffer in self._spare[:3])
        if self.radial:
            self.w = self._spare[3][:start[-1]]
        self._spare = old
        return start

    def snapshot(self) -> CellSums:
        """The moments of the current particles on the output grid."""
        frame = self.output_sums()
        self.sample_into(frame)
        return frame

    def sample_into(self, frame: CellSums):
        """Add the current particles' moments to ``frame``: the sums of the
        last step's cells where ``frame`` is on the same grid (the step
        conserved them), else one pass over the particles."""
        if frame.same_grid(self.cells):
            frame.add_sums(self.cells)
        else:
            frame.add(self.x, self.v, self.e, self.w)

    def output_sums(self) -> CellSums:
        """Empty moment sums on the scene's output grid."""
        out = self.scene.output
        return CellSums([lo for lo, _ in out.domain], out.spacing, out.shape, self.output_fraction, self.radial)

    def _side_forces(self, delivered, dt) -> np.ndarray:
        """Per side: the momentum the particles handed to a reflecting side
        over the step, over dt; elsewhere the pressure of the adjacent cells
        times the side's area (2D: its length per metre depth, or the
        revolved side in r–z)."""
        dim = self.scene.dim
        forces = delivered * self.mass / dt
        p = self.state.p
        for side in range(2 * dim):
            if self.sides[side] != REFLECT:
                area = self.scene.side_area(self.scene.sides[side]) if dim > 1 else 1.0
                forces[side] = float(np.nanmean(p[boundary_layer(side, dim)])) * area
        return forces


def appended(a: np.ndarray, parts: list) -> np.ndarray:
    """``a`` followed by the arrays ``parts``: written into the room behind
    ``a`` in its buffer (:func:`_buffer_of`) where there is enough, so that
    the particles an inflow adds do not copy all the others; else into a
    new buffer with room (:func:`~partmesh.particle.dsmc.cells.with_room`)."""
    n, k = a.shape[0], sum(part.shape[0] for part in parts)
    buffer = _buffer_of(a)
    if buffer.shape[0] < n + k:
        buffer = np.empty((with_room(n + k), *a.shape[1:]))
        buffer[:n] = a
    for part in parts:
        buffer[n:n + part.shape[0]] = part
        n += part.shape[0]
    return buffer[:n]


def _buffer_of(a: np.ndarray) -> np.ndarray:
    """The array ``a`` is the leading part of (itself, or its base)."""
    b = a.base
    if isinstance(b, np.ndarray) and b.ndim == a.ndim and b.ctypes.data == a.ctypes.data and b.flags.c_contiguous:
        return b
    return a


def _side_kind(boundary) -> int:
    if boundary == "reflect":
        return REFLECT
    if boundary == "periodic":
        return PERIODIC
    return OPEN


class _Run(RunRecord):
    """The record of one DSMC run; ``sums`` gathers the moments of the
    frame under way (the last ``window`` steps before its output time)."""

    def __init__(self, scene, gas, settings, compile_seconds):
        self.scene, self.gas = scene, gas
        points = np.array([pr.at(scene.dim) for pr in scene.probes], dtype=float).reshape(-1, scene.dim)
        self.read = probe_cells(gas.cells, points, [pr.shell for pr in scene.probes])
        super().__init__(scene, "dsmc", settings, compile_seconds, History(self.probes(), 2 * scene.dim, scene.t_start))
        self.sums = gas.output_sums()
        self.solid = None
        if scene.obstacles:
            X, Y = np.meshgrid(scene.output.x, scene.output.y)
            self.solid = np.any([shape.contains(X, Y) for shape in scene.obstacles], axis=0)

    def probes(self) -> np.ndarray:
        """Pressure at every probe: that of the DSMC cell holding it, or the
        mean over its shell (:func:`~partmesh.particle.dsmc.sample.probe_cells`),
        each cell's unbiased (:func:`~partmesh.particle.dsmc.sample.unbiased_pressure`)."""
        gas = self.gas
        p = unbiased_pressure(gas.state.p.reshape(-1), gas.cells.count, self.scene.dim, gas.zeta)
        return probe_pressures(p, self.read)

    def totals(self, gas) -> dict:
        """Mass and energy (translational and internal) of all particles."""
        mass, energy = gas.totals()
        return {"mass": mass, "energy": energy}

    def fields(self, gas) -> dict:
        """The fields of the particles as they are (a partial result's last frame)."""
        return self._fields_of(gas.snapshot())

    def output_frame(self, gas) -> dict:
        """The fields of the moments gathered since the last frame (those of
        the particles as they are if no step came before: t = 0)."""
        if self.sums.samples == 0:
            gas.sample_into(self.sums)
        fields, self.sums = self._fields_of(self.sums), gas.output_sums()
        return fields

    def _fields_of(self, frame: CellSums) -> dict:
        values = frame.state(self.gas.mass, self.scene.gamma)._asdict()
        if self.solid is not None:
            for q in values.values():
                q[self.solid] = np.nan
        return {name: values[name] for name in self.scene.fields}

    def saved(self) -> dict:
        return {**super().saved(), "sums": self.sums}

    def restore(self, saved: dict) -> None:
        super().restore(saved)
        self.sums = saved["sums"]

    def output(self) -> Output:
        fields = {name: self.stacked(name) for name in self.scene.fields}
        s = self.settings
        about = (" about MC-limited linear profiles of the velocity and temperature across the cell"
                 if self.gas.profile == "linear" else "")
        when = (", each cell at its own Courant step (a multiple of the global step set by the fastest cell)"
                if self.gas.hold is not None else "")
        cells = (f"per-cell equilibrium redraw{about} conserving momentum and energy{when}" if self.gas.vhs is None else
                 f"no-time-counter VHS collisions (omega {s['omega']:g}) with Larsen-Borgnakke rotational exchange "
                 f"(Z_rot {s['z_rot']:g}), mean free path {s['mean_free_path']:g} m at the lowest initial density")
        scheme = (f"{'equilibrium DSMC (Pullin)' if self.gas.vhs is None else 'DSMC'}: free flight, specular plane "
                  f"walls and obstacle polygons, equilibrium reservoirs at open sides, {cells}; {s['ppc']} particles "
                  f"per cell in the lowest initial density, moments over {s['window']} step(s) per frame")
        shells = [pr.name for pr in self.scene.probes if pr.shell]
        shell_note = (f"; shell probes ({', '.join(shells)}): the volume-weighted mean pressure of the cells within "
                      "half a cell of the sphere (r-z) or circle through them about the origin" if shells else "")
        attrs = {"particle_mass": self.gas.mass, "internal_degrees": self.gas.zeta,
                 "wall_reflections": self.gas.safeguard,  # particles the safeguard put back out of a solid
                 "particles_in_solids": self.gas.in_solids(), "obstacle_bounces": self.gas.bounces,
                 "collisions": self.gas.collisions,
                 "wall_pressure": "reflecting sides: momentum delivered by the particles; other sides: the "
                                  "adjacent cell's pressure; probes: the pressure of the cell holding them, freed "
                                  "of the bias of one sample's thermal energy" + shell_note}
        return Output(fields, self.solid, scheme, int(self.gas.x.shape[0]), attrs)
