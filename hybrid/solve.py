"""Hybrid finite-volume – SPH (method ``hybrid``; after Myers, Musk, Palmer &
Palmer 2024, Front. Phys. 11, 1325294): a coarse MUSCL–Hancock grid
everywhere, SPH particles only in the cells that need them.

One step of the coupled system, from t to t + Δt (Δt: the grid's CFL step):

1. The grid takes its finite-volume step everywhere: U_fv(t + Δt).
2. The particles sub-cycle from t to t + Δt with the SPH leapfrog
   (:mod:`partmesh.particle.sph.integrator`), the last sub-step trimmed to land on
   t + Δt. Their neighbours at the edge are boundary particles on the
   injection lattice of a ring of cells around the particle cells, which
   move with the grid's velocity and take the grid's state, interpolated
   in space (bilinear) and in time (linear between U(t) and U_fv), at
   every sub-step. Roles hold over the step (step 5 changes them), so
   the sub-steps share one particle set and reuse its neighbour lists.
3. Conservation: the grid's step fixes what the particle cells hold at
   t + Δt (Σ_cells U_fv: the flux through their edge), and the particles'
   mass, momentum and energy are matched to it (:func:`partmesh.hybrid.exchange.matched`;
   momentum not along an axis where the particle cells meet a wall: the
   grid's coarse wall and the particles' mirror wall push differently, and
   a common velocity shift for the difference, measured on ``blast_kt``,
   slowed the shock by 9 % at 0.2 ms).
4. The particles are deposited back onto their cells (mass, momentum and
   energy, cloud-in-cell, with the boundary particles' clouds reaching
   in); the other cells keep U_fv. The
   total of the grid is then the finite-volume step's: it changes only
   through the domain's sides, to round-off.
5. Cells are flagged anew (relative jump of ρ or p, of p alone, or of p
   across faces the flow does not diverge across, to a face neighbour
   above ``threshold``: :func:`partmesh.hybrid.cells.sensed_jumps`; plus ``buffer``
   cells; a flagged cell stays flagged
   until its jumps fall below a quarter of that): fluid particles in the
   ring become boundary particles and those beyond it are removed;
   boundary particles in flagged cells join the fluid; flagged cells left
   with under a quarter of their lattice, or holding a particle more than
   ``COARSEST`` (4) times heavier than a lattice particle at its density
   (dense gas expanded into rarefied gas: its support, and the ring around
   it, would span many cells), and ring cells with under half, get the
   lattice with the cell's state.

``dx`` is the particle spacing; the grid's cells are ``dx / beta`` wide
(``beta`` = Δx_SPH/Δx_FV = 1/4: four particles per cell width).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.cases.checkpoint import checkpoint_for
from partmesh.cases.compiling import compiling
from partmesh.cases.history import History, Output, RunRecord
from partmesh.cases.march import DT_FLOOR, Start, Stepping, march, single_steps
from partmesh.compare.regrid import to_output_grid
from partmesh.gridref.euler.setup import inflow_states, initial_state, scheme_for
from partmesh.gridref.euler.state import primitive
from partmesh.gridref.euler.step import Stepper
from partmesh.gridref.grid import bilinear_stencil, cell_centres, solver_grid
from partmesh.gridref.jax_setup import configure_jax
from partmesh.hybrid.cells import cell_of, flagged, lattice, relaid, ring, sensed_jumps, thinned
from partmesh.hybrid.exchange import cloud, deposited, interpolated, matched
from partmesh.hybrid.method import HybridSettings
from partmesh.particle.sph.integrator import SEARCH_SLACK, Switches, Unstable, leapfrog, time_step
from partmesh.particle.sph.scheme import Evaluation, GasSPH, Particles

#: a cell keeps its particles until its jumps fall below this fraction of the threshold
RELEASE = 0.25
#: a cell gets its lattice back when one of its particles carries more than
#: this multiple of the mass a lattice particle would carry at its density
#: (ρ Δx^d): a particle of dense gas that has expanded into rarefied gas
COARSEST = 4.0

#: what a checkpoint keeps of the coupling: the counts of sub-steps and particles over the run
COUNTS = ("substeps", "particle_steps", "most_particles", "fluid_steps", "most_fluid")


@dataclass
class State:
    """The coupled state: conservative grid variables ``U`` (every cell),
    the particle cells ``owned`` (flat bool), the fluid particles ``P`` with
    their evaluation ``E`` (None where no cell owns particles) and the
    boundary particles' positions ``xb`` and masses ``mb``."""

    U: tuple
    owned: np.ndarray
    P: Particles | None
    E: Evaluation | None
    xb: np.ndarray
    mb: np.ndarray


class Coupling:
    """The grid, the particles and what passes between them, for one run."""

    def __init__(self, scene, grid, stepper, sph, per_cell, eta, threshold, sensor, buffer, switches, cfl_sph,
                 dt_floor):
        self.scene, self.grid, self.stepper, self.sph = scene, grid, stepper, sph
        self.per_cell, self.eta, self.threshold, self.buffer = per_cell, eta, threshold, buffer
        self.sensor = sensor
        self.switches, self.cfl_sph, self.dt_floor = switches, cfl_sph, dt_floor
        self.dim, self.gamma = scene.dim, scene.gamma
        self.shape = tuple(grid.shape)  # cells per axis x[, y]
        self.field_shape = self.shape[::-1]  # the field layout ([y,] x)
        self.lo = np.array([lo for lo, _ in scene.domain])
        self.cell = np.array(grid.step, float)
        self.volume = float(np.prod(self.cell))
        self.n_cells = int(np.prod(self.shape))
        self.lattice_count = per_cell ** self.dim
        self.periodic = tuple(scene.periodic) + (False,) * (2 - self.dim)
        #: sub-steps taken and the particle-steps they cost (particles × sub-steps), over the run, of
        #: all particles and of the fluid ones alone (the rows of the SPH sums: boundary particles are
        #: only neighbours)
        self.substeps, self.particle_steps, self.most_particles = 0, 0, 0
        self.fluid_steps, self.most_fluid = 0, 0
        self.error = None

    # --- the grid's state where the particles need it ---

    def primitive(self, U) -> np.ndarray:
        """Primitive fields (ρ, u[, v], p) of ``U`` as one array (2 + d, [ny,] nx)."""
        return np.stack([np.asarray(a) for a in primitive(U, self.gamma)])

    def stencil(self, x):
        return bilinear_stencil(self.grid, x, self.periodic)

    def cells(self, x) -> np.ndarray:
        """The flat cell of each position ``x`` (n, d)."""
        return cell_of(x, self.lo, self.cell, self.shape)

    def boundary(self, W, x, m):
        """Imposed particles ``(x, v, rho, u, H, m)`` at ``x`` with masses ``m``
        and the grid's primitive state ``W`` there."""
        values = interpolated(W, self.stencil(x))
        rho, v, p = values[0], values[1:1 + self.dim].T.copy(), values[-1]
        return x, v, rho, p / ((self.gamma - 1.0) * rho), self.eta * (m / rho) ** (1.0 / self.dim), m

    def fluid(self, W, x, m) -> Particles:
        """Fluid particles at ``x`` with masses ``m`` and the grid's state ``W`` there."""
        _, v, rho, u, H, _ = self.boundary(W, x, m)
        n = x.shape[0]
        return Particles(x=x, v=v, u=u, m=m, H=H, alpha=np.full(n, self.switches.alpha_min), alpha_u=np.zeros(n),
                         rho=rho, products=np.zeros(n, bool))

    def free_axes(self, inside: np.ndarray) -> np.ndarray:
        """Per axis x[, y]: whether the particle cells ``inside`` (field
        layout) stay clear of the reflecting sides across that axis, so
        their momentum along it changes only through the grid's flux."""
        free = np.ones(self.dim, bool)
        for a in range(self.dim):
            for k, side in ((0, f"{'xy'[a]}_lo"), (-1, f"{'xy'[a]}_hi")):
                edge = np.take(inside, k, axis=self.dim - 1 - a)
                if self.scene.boundaries[side] == "reflect" and edge.any():
                    free[a] = False
        return free

    def around(self, P: Particles, owned) -> np.ndarray:
        """The ring of cells for the boundary particles: the cells outside
        ``owned`` that the support (with the search margin) of a fluid
        particle reaches, counted in whole cells from the particle's cell,
        and two more: a narrower ring (measured on ``sod``) lets more noise
        in at its edge. Each particle reaches only as far as its own support,
        so the wide supports of rarefied gas widen the ring only beside it."""
        reach = np.zeros(self.n_cells, np.int64)
        np.maximum.at(reach, self.cells(P.x), np.ceil(SEARCH_SLACK * P.H / self.cell[0]).astype(np.int64) + 3)
        return ring(owned.reshape(self.field_shape), reach.reshape(self.field_shape), self.periodic).ravel()

    # --- particles from the grid ---

    def seeded(self, cells, U) -> Particles:
        """The injection lattice of ``cells`` carrying each cell's mass,
        momentum and energy exactly (equal masses within a cell)."""
        x, owner = lattice(cells, self.lo, self.cell, self.shape, self.per_cell)
        q = np.stack([np.asarray(a).ravel()[owner] for a in U])
        rho, v = q[0], (q[1:1 + self.dim] / q[0]).T.copy()
        u = q[-1] / rho - 0.5 * np.sum(v * v, axis=1)
        m = rho * self.volume / self.lattice_count
        n = x.shape[0]
        return Particles(x=x, v=v, u=u, m=m, H=self.eta * (m / rho) ** (1.0 / self.dim),
                         alpha=np.full(n, self.switches.alpha_min), alpha_u=np.zeros(n), rho=rho,
                         products=np.zeros(n, bool))

    def regrouped(self, U, P: Particles | None, xb, mb, owned_before) -> State:
        """The state after the cells are flagged anew from ``U`` (a cell
        that held particles, ``owned_before``, keeps them until its jumps
        fall below ``RELEASE`` times the threshold: without this hysteresis,
        cells at the edge of the region would change sides step after step,
        each time trading particle state for grid state, which shows as
        noise): fluid
        particles in flagged cells, boundary particles in the ring around
        them (a particle crossing from one to the other changes its role,
        one outside both is removed), the lattice in flagged cells left with
        under a quarter of it or holding a particle heavier than ``COARSEST``
        lattice particles at its density, and in ring cells left with under
        half, and the particles' evaluation with their new boundary."""
        W = self.primitive(U)
        jumps = sensed_jumps(W, self.sensor, self.periodic)
        owned = flagged(jumps, self.threshold, self.buffer, self.periodic).ravel()
        if owned_before.any():
            owned |= owned_before & flagged(jumps, RELEASE * self.threshold, self.buffer, self.periodic).ravel()
        if not owned.any():
            return State(U, owned, None, None, np.zeros((0, self.dim)), np.zeros(0))
        P = P if P is not None else self.seeded(np.zeros(0, np.int64), U)
        # boundary particles now in flagged cells join the fluid with the grid's state
        joins = owned[self.cells(xb)]
        P.append(self.fluid(W, xb[joins], mb[joins]))
        xb, mb = xb[~joins], mb[~joins]
        fill = owned & relaid(self.cells(P.x), P.m, P.rho, self.n_cells, self.lattice_count, self.volume, COARSEST)
        if fill.any():
            P = P.take(np.flatnonzero(~fill[self.cells(P.x)]))
            P.append(self.seeded(np.flatnonzero(fill), U))
        around = self.around(P, owned)
        # fluid particles now in the ring become boundary particles; outside both, they go
        cell = self.cells(P.x)
        leaving = around[cell]
        xb, mb = np.concatenate([xb, P.x[leaving]]), np.concatenate([mb, P.m[leaving]])
        P = P.take(np.flatnonzero(owned[cell]))
        keep = around[self.cells(xb)]
        xb, mb = xb[keep], mb[keep]
        thin = around & thinned(self.cells(xb), self.n_cells, 0.5 * self.lattice_count)
        if thin.any():
            keep = ~thin[self.cells(xb)]
            new, _ = lattice(np.flatnonzero(thin), self.lo, self.cell, self.shape, self.per_cell)
            rho = interpolated(W[:1], self.stencil(new))[0]
            xb = np.concatenate([xb[keep], new])
            mb = np.concatenate([mb[keep], rho * (self.volume / self.lattice_count)])
        self.sph.verlet.forget()
        E = self.sph.evaluate(P, P.x, P.v, P.u, self.boundary(W, xb, mb))
        P.H, P.rho = E.H, E.rho
        self.most_particles = max(self.most_particles, P.x.shape[0] + xb.shape[0])
        self.most_fluid = max(self.most_fluid, P.x.shape[0])
        return State(U, owned, P, E, xb, mb)

    # --- one step of the coupled system ---

    def step(self, S: State, t: float, dt: float):
        """``(state at t + dt, CFL step of the grid, side forces)``; the CFL
        step is NaN if the step failed (``self.error`` says why)."""
        U_fv, dt_cfl, forces, _ = self.stepper(S.U, dt, t)
        if not np.isfinite(float(dt_cfl)):
            self.error = None
            return S, float("nan"), forces
        U_new, P, xb, mb = U_fv, None, S.xb, S.mb
        if S.P is not None:
            try:
                W1 = self.primitive(U_fv)
                P, xb, mb = self.substepped(S, self.primitive(S.U), W1, t, dt)
                inside = S.owned.reshape(self.field_shape)
                target = np.array([float(jnp.sum(jnp.where(inside, a, 0.0))) for a in U_fv]) * self.volume
                # the boundary particles' clouds reaching into the particle cells, at the grid's new state
                _, vb, _, ub, _, _ = self.boundary(W1, xb, mb)
                edge = deposited(cloud(self.stencil(xb), S.owned), mb, vb, ub, self.n_cells, self.volume)
                weights = cloud(self.stencil(P.x), S.owned)
                P = matched(P, weights[1].sum(axis=1), target - edge.sum(axis=1) * self.volume,
                            self.free_axes(inside))
            except FloatingPointError as err:
                self.error = f"hybrid failed at t = {t + dt:.6g} s: {err}."
                return S, float("nan"), forces
            D = deposited(weights, P.m, P.v, P.u, self.n_cells, self.volume) + edge
            U_new = tuple(jnp.where(inside, d.reshape(self.field_shape), a) for d, a in zip(D, U_fv))
        return self.regrouped(U_new, P, xb, mb, S.owned), float(dt_cfl), forces

    def substepped(self, S: State, W0, W1, t: float, dt: float):
        """The fluid particles, and the boundary particles' positions and
        masses, advanced from ``t`` to ``t + dt`` in SPH sub-steps, with the
        boundary state interpolated between ``W0`` (at t) and ``W1`` (at
        t + dt); boundary particles move with the grid's velocity. Every
        particle keeps its role over the step (roles change in
        :meth:`regrouped`, at its end: a particle moves less than a cell in
        one grid step), so the particle set, and with it the neighbour
        lists, stays the same across the sub-steps: a Verlet list serves
        until the particles have moved through its skin."""
        P, E, xb, mb = S.P, S.E, S.xb, S.mb
        _, vb, _, ub, Hb, _ = self.boundary(W0, xb, mb)
        s, t1 = t, t + dt
        while s < t1 * (1 - 1e-14):
            cb = np.sqrt(self.gamma * (self.gamma - 1.0) * ub)
            ds = min(time_step(P, E, self.cfl_sph),
                     self.cfl_sph * float(np.min(0.5 * Hb / (cb + np.linalg.norm(vb, axis=1)), initial=np.inf)))
            if not ds >= self.dt_floor:  # (NaN too)
                raise FloatingPointError(f"the particles' sub-step collapsed to {ds:.3g} s at t = {s:.6g} s")
            ds = min(ds, t1 - s)
            xb = self.sph.verlet.wrapped(xb + ds * vb)
            a = (s + ds - t) / dt
            imposed = self.boundary((1.0 - a) * W0 + a * W1, xb, mb)
            _, vb, _, ub, Hb, _ = imposed
            try:
                P, E, _ = leapfrog(self.sph, P, E, ds, self.switches, imposed)
            except Unstable as err:
                raise FloatingPointError(f"the particles became unstable ({err})") from None
            s = t1 if s + ds >= t1 * (1 - 1e-14) else s + ds
            self.substeps += 1
            self.particle_steps += P.x.shape[0] + xb.shape[0]
            self.fluid_steps += P.x.shape[0]
        return P, xb, mb


def solve(scene, settings: HybridSettings):
    """Run ``scene`` with the hybrid finite-volume – SPH method and checked
    ``settings`` (:class:`~partmesh.hybrid.method.HybridSettings`). Raises
    :class:`~partmesh.cases.errors.SolverFailed` with the partial result if the
    state turns non-physical or the run is interrupted. Checkpoints as in
    the other methods (:mod:`partmesh.cases.checkpoint`): a resumed run searches its
    particles' neighbours anew, so it ends within ~1e-7 of an
    uninterrupted one.
    """
    configure_jax()
    dx, per_cell = settings.dx, settings.per_cell
    kernel, eta, alpha_max, alpha_min, alpha_u, limiter, riemann, sensor = (
        settings.kernel, settings.eta, settings.alpha_max, settings.alpha_min, settings.alpha_u, settings.limiter,
        settings.riemann, settings.sensor)
    grid = solver_grid(scene.domain, dx * per_cell)
    U = initial_state(scene, grid)
    stepper = Stepper(scheme_for(scene, grid, settings.cfl, limiter, riemann),
                      inflow=lambda t: inflow_states(scene, t))
    lo, hi = np.array([a for a, _ in scene.domain]), np.array([b for _, b in scene.domain])
    region = [(a, b) for a, b in zip(lo, hi)]
    open_ = tuple(side for side in scene.sides if scene.boundaries[side] == "outflow")
    sph = GasSPH(scene, kernel, eta, region, open_)
    coupling = Coupling(scene, grid, stepper, sph, per_cell, eta, settings.threshold, sensor, settings.buffer,
                        Switches(alpha_max, alpha_min, alpha_u), settings.cfl_sph, DT_FLOOR * settings.t_end)
    with compiling("hybrid", settings.progress) as compiled:
        jax.block_until_ready(stepper.one_step(stepper.start(U), 0.0, 0.0))
        # (the first evaluation compiles, or loads, the SPH kernels)
        S = coupling.regrouped(U, None, np.zeros((0, scene.dim)), np.zeros(0), np.zeros(coupling.n_cells, bool))
        if S.P is not None:
            sph.compile_rest(S.P, S.E)
    compile_seconds = compiled.seconds
    probe_points = [pr.at(scene.dim) for pr in scene.probes] or [(0.0,) * scene.dim]
    probe_stencil = bilinear_stencil(grid, probe_points, coupling.periodic)
    run = _Run(scene, coupling, settings.record(), compile_seconds,
               History(interpolated(coupling.primitive(U)[-1:], probe_stencil)[0][: len(scene.probes)], 2 * scene.dim,
                       scene.t_start))
    t, dt_cfl = scene.t_start, float(stepper.initial_dt(U))
    ckpt = checkpoint_for(scene, settings)
    saved = ckpt.saved_state(run)
    if saved is not None:
        S, t, dt_cfl = saved["S"], saved["t"], saved["dt_cfl"]
        S.U = tuple(jnp.asarray(a) for a in S.U)
        for name, value in saved["counts"].items():
            setattr(coupling, name, value)
        sph.seconds, sph.force_interactions = saved["sph_seconds"], saved["force_interactions"]

    def step(S, t, dt_cfl, t_out):
        dt = min(dt_cfl, t_out - t)
        S_new, dt_cfl, forces = coupling.step(S, t, dt)
        if not np.isfinite(dt_cfl):
            return S, dt, dt_cfl, None
        probes = interpolated(coupling.primitive(S_new.U)[-1:], probe_stencil)[0][: len(scene.probes)]
        return S_new, dt, dt_cfl, (probes, forces)

    def diagnose(S, t, step, dt, failed):
        return coupling.error or f"hybrid's grid step turned the state non-physical at t = {t:.6g} s (step {step})."

    def saved_state(S, t, dt_cfl):
        return {"S": dataclasses.replace(S, U=tuple(np.asarray(a) for a in S.U)), "t": t, "dt_cfl": dt_cfl,
                "counts": {name: getattr(coupling, name) for name in COUNTS},
                "sph_seconds": dict(sph.seconds), "force_interactions": sph.force_interactions}

    return march(run, Start(S, t, dt_cfl), Stepping(single_steps(step), saved_state, diagnose), ckpt, settings)


class _Run(RunRecord):
    """The record of one hybrid run: frames are the grid's fields on the
    output grid, with the particles' (Shepard interpolation) where they own
    the cells."""

    def __init__(self, scene, coupling, settings, compile_seconds, history):
        super().__init__(scene, "hybrid", settings, compile_seconds, history)
        self.coupling = coupling
        out = scene.output
        points = np.stack(np.meshgrid(*([out.x] if scene.dim == 1 else [out.x, out.y])), axis=-1).reshape(-1, scene.dim)
        #: the grid cell of every output point, in the output layout
        self.out_cell = cell_of(points, coupling.lo, coupling.cell, coupling.shape)

    def totals(self, S: State) -> dict:
        """Mass and energy on the grid (per metre depth in 2D; the particles'
        are deposited on it after every step)."""
        return {name: float(jnp.sum(S.U[k])) * self.coupling.volume for name, k in (("mass", 0), ("energy", -1))}

    def fields(self, S: State) -> dict:
        scene, c = self.scene, self.coupling
        W = c.primitive(S.U)
        values = {"rho": W[0], "u": W[1], "p": W[-1], "e": W[-1] / ((scene.gamma - 1.0) * W[0])}
        if scene.dim == 2:
            values["v"] = W[2]
        src = cell_centres(c.grid)
        out = scene.output
        pairs = (src[0], out.x) if scene.dim == 1 else (src[0], out.x, src[1], out.y)
        grids = np.stack([to_output_grid(values[f], *pairs, periodic=c.periodic)[0] for f in scene.fields])
        if S.P is not None:
            P, E = S.P, S.E
            particle = {"rho": E.rho, "u": P.v[:, 0], "p": (scene.gamma - 1.0) * E.rho * P.u, "e": P.u}
            if scene.dim == 2:
                particle["v"] = P.v[:, 1]
            axes = (out.x,) if scene.dim == 1 else (out.x, out.y)
            sph = c.sph.interpolate(P, E, np.stack([particle[f] for f in scene.fields]), axes)
            where = S.owned[self.out_cell].reshape(grids.shape[1:])
            grids = np.where(where & np.isfinite(sph), sph, grids)
        return dict(zip(scene.fields, grids))

    def output(self) -> Output:
        s, c = self.settings, self.coupling
        fields = {name: self.stacked(name) for name in self.scene.fields}
        scheme = (f"hybrid: unsplit MUSCL-Hancock ({s['limiter']}, {s['riemann'].upper()}) on cells "
                  f"{c.cell[0]:g} m wide; grad-h SPH ({s['kernel']}, H = {s['eta']:g} (m/rho)^(1/d), Cullen-Dehnen "
                  f"viscosity, conduction) at spacing {s['dx']:g} m in the cells where the jump of "
                  f"{s['sensor']} (sensor) exceeds {s['threshold']:g} (+ {s['buffer']} cells), sub-cycled; "
                  "boundary particles from the grid; particles matched to the grid's flux and deposited back "
                  "(cloud-in-cell, conservative)")
        attrs = {"fv_cells": c.n_cells, "particles_max": c.most_particles, "sph_substeps": c.substeps,
                 "particle_steps": c.particle_steps, "fluid_particles_max": c.most_fluid,
                 "fluid_particle_steps": c.fluid_steps, "neighbour_searches": c.sph.counters[1],
                 **{f"seconds_{name}": seconds for name, seconds in c.sph.counters[0].items()},
                 "deposition": "grid fields linearly interpolated; Shepard interpolation of the particles "
                               "in the cells that hold them"}
        return Output(fields, None, scheme, c.n_cells + c.most_particles, attrs)
