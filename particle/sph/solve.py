"""Gas SPH (method ``sph``): run a scene, return a schema Dataset on the
scene's output grid (Prasanna Kumar, Patnaik & Ramamurthi 2018, Phys.
Fluids 30, 046105; Price 2012, J. Comput. Phys. 231, 759), planar or
axisymmetric (ring masses, :mod:`partmesh.particle.sph.axis`; García-Senz
et al. 2009, MNRAS 392, 346).

Time integration is the predictor–corrector leapfrog of
:mod:`partmesh.particle.sph.integrator` with Δt = C min_i h_i / v_sig,i, h = H/2, C = 0.25.
"""

from __future__ import annotations


import numba
import numpy as np
import xarray as xr

from partmesh.cases.checkpoint import checkpoint_for
from partmesh.cases.checks import check_obstacles
from partmesh.cases.compiling import compiling
from partmesh.cases.errors import SolverFailed
from partmesh.cases.history import History, Output, RunRecord
from partmesh.cases.march import StepFailed, landed
from partmesh.cases.scene import Inflow
from partmesh.compare.io import particle_snapshot
from partmesh.particle.cell_grid import sort_order
from partmesh.particle.march import march_particles
from partmesh.particle.sph.inflow import InflowBuffer
from partmesh.particle.sph.integrator import MIN_STEP_FRACTION, Switches, Unstable, leapfrog, time_step
from partmesh.particle.sph.materials import charged_state
from partmesh.particle.sph.method import SPHSettings, has_inlet
from partmesh.particle.sph.particles import (
    check_supported,
    extended_domain,
    initial_state,
    lattice_volumes,
    outflow_reach,
    place_1d,
    place_2d,
    place_lattice,
)
from partmesh.particle.sph.sampling import shepard_at_points
from partmesh.particle.sph.scheme import Evaluation, GasSPH, Particles
from partmesh.particle.sph.switches import conduction_switch, cullen_dehnen
from partmesh.particle.sph.wall_placement import walls
from partmesh.particle.sph.wall_state import virtual_state

#: particle kinds in a snapshot
KINDS = {"fluid": 0, "wall": 1, "buffer": 2}
#: the growth of a support the inflow buffer's depth and the outflow margin allow for
SUPPORT_GROWTH = 1.15
#: the particle arrays are re-sorted along the search cells every so many steps
RESORT_STEPS = 10


def solve(scene, settings: SPHSettings):
    """Run ``scene`` with compressible SPH and checked ``settings``
    (:class:`~partmesh.particle.sph.method.SPHSettings`).

    Raises :class:`~partmesh.cases.errors.SolverFailed` with the partial result if
    the state turns non-physical or the run is interrupted. Checkpoints as
    in the other methods (:mod:`partmesh.cases.checkpoint`); a resumed run searches
    its neighbour lists anew, so the density solve, converged to 1e-8 in H,
    starts from other brackets and the run matches an uninterrupted one to
    ~1e-7, not bit for bit.
    """
    check_supported(scene)
    dx, t_end, dim, masses = settings.dx, settings.t_end, scene.dim, settings.masses
    check_obstacles(scene, dx)
    cfl, eta, alpha_max, alpha_min, alpha_u = (settings.cfl, settings.eta, settings.alpha_max, settings.alpha_min,
                                               settings.alpha_u)
    switches = Switches(alpha_max, alpha_min, alpha_u)
    reach = outflow_reach(scene, dx, t_end, 4.0 * SUPPORT_GROWTH * eta * dx)
    box = extended_domain(scene, reach)
    P = _initial_particles(scene, dx, eta, alpha_min, box, masses)
    inflow = _inflow_buffer(scene, P, eta)
    # virtual particles reach twice the initial support into the solids
    sph = GasSPH(scene, settings.kernel, eta, box, tuple(side for side, r in reach.items() if r == 0.0),
                 walls(scene, dx, 2.0 * eta * dx, box) if dim == 2 else None)
    # the first evaluation, switch update and interpolation compile (or load) the numba kernels, and
    # compile_rest those a run meets later
    with compiling("sph", settings.progress) as compiled:
        try:
            E = sph.evaluate(P, P.x, P.v, P.u, _buffer(inflow, 0.0, eta, P.m[0]))
        except FloatingPointError as err:
            raise SolverFailed(f"sph failed on the initial state: {err}.") from None
        P.alpha = cullen_dehnen(P.alpha, E.div_v, E.div_v, E.curl_v, E.vsig, E.H, 1.0, alpha_max, alpha_min)
        P.alpha_u = conduction_switch(P.alpha_u, E.lap_u, P.u, E.vsig, E.H, 1.0, alpha_u, 0.0)
        sph.compile_rest(P, E)
        sample_points = _sample_points(scene)
        probes0 = _pressure_at(sph, P, E, sample_points)[: len(scene.probes)]
    compile_seconds = compiled.seconds
    # the pass timings and counts exclude compilation
    sph.counters = {"search": 0.0, "density": 0.0, "forces": 0.0}, 0, 0
    P.H, P.rho = E.H, E.rho
    _observe_inlet(inflow, P, E, 0.0, eta)
    run = _Run(scene, sph, settings.record(), compile_seconds, History(probes0, 2 * dim, scene.t_start))
    t = scene.t_start
    ckpt = checkpoint_for(scene, settings)
    saved = ckpt.saved_state(run)
    if saved is not None:
        P, E, t = saved["P"], saved["E"], saved["t"]
        run.reflections = saved["reflections"]
        sph.counters = saved["counters"]
        sph.verlet.forget()
        if inflow:
            inflow.inflowed, inflow.entered, inflow.adjacent = saved["inflow"]

    def step(state, t, dt_cfl, t_out):
        P, E = state
        if run.n_steps % RESORT_STEPS == 0:
            # neighbours next to each other in memory: particles sorted cell by cell
            order = sort_order(P.x, sph.lo, sph.hi, 0.5 * float(np.median(E.H)))
            P, E = P.take(order), E.take(order)
            sph.verlet.renumber(order)
        try:
            dt_stable = time_step(P, E, cfl, MIN_STEP_FRACTION * t_end)
            dt = min(dt_stable, t_out - t)
            # the layer moves over the step first, so that the buffer at t + dt no longer holds
            # the columns that crossed the inlet and join the fluid with the boundary state
            entering = _entering(inflow, t, dt, eta, P.m[0], alpha_min) if inflow else None
            Q, E_new, reflected = leapfrog(sph, P, E, dt, switches, _buffer(inflow, t + dt, eta, P.m[0]), entering,
                                           lambda Q: sph.retained(Q.x))
        except Unstable as err:
            raise StepFailed(f"sph became unstable at t = {t:.6g} s (step {run.n_steps + 1}): {err}.") from None
        except FloatingPointError as err:
            raise StepFailed(f"sph failed at t = {t + dt:.6g} s (step {run.n_steps + 1}): {err}.") from None
        run.reflections += reflected
        t_new = landed(t, dt, t_out)
        _observe_inlet(inflow, Q, E_new, t_new, eta)
        if t_new < run.history.t[-1] + scene.output.dt_probe * (1 - 1e-9) and t_new != t_out:
            return (Q, E_new), dt, dt_stable, None
        sampled = _pressure_at(sph, Q, E_new, sample_points)
        return (Q, E_new), dt, dt_stable, (sampled[: len(scene.probes)], _side_forces(scene, sampled))

    def saved_state(state, t, dt_cfl):
        P, E = state
        return {"P": P, "E": E, "t": t, "reflections": run.reflections, "counters": sph.counters,
                "inflow": (inflow.inflowed, inflow.entered, inflow.adjacent) if inflow else None}

    return march_particles(run, (P, E), t, step, ckpt, saved_state, settings, P.x.shape[0],
                           lambda state, t: _snapshot(sph, state[0], inflow, t))


def _snapshot(sph, P: Particles, inflow, t: float) -> xr.Dataset:
    """The particles at time ``t`` (SPEC §2): fluid, the walls' virtual
    particles and the inflow buffer, with their kind."""
    gamma = sph.scene.gamma
    groups = [(P.x, P.v, P.rho, P.u, P.H, P.m, KINDS["fluid"])]
    if sph.wall is not None:
        groups.append((*virtual_state(sph.wall, P.x, P.v, P.rho, (gamma - 1.0) * P.rho * P.u, P.m, P.H, sph.kind,
                                      sph.eta, gamma), KINDS["wall"]))
    if inflow is not None:
        groups.append((*_buffer(inflow, t, sph.eta, P.m[0]), KINDS["buffer"]))
    x, v, rho, u, H, m = (np.concatenate(parts) for parts in list(zip(*groups))[:6])
    rho = sph.gas_density(x, H, rho)
    kind = np.concatenate([np.full(g[0].shape[0], g[6], np.int8) for g in groups])
    products = np.concatenate([P.products, np.zeros(x.shape[0] - P.x.shape[0], bool)])
    return particle_snapshot(x, v, rho, sph.materials.pressure(rho, u, products), m, H, kind, KINDS, sph.scene.name,
                             "sph", t)


def _initial_particles(scene, dx, eta, alpha_min, box, masses="equal") -> Particles:
    """Particles over ``box`` (the domain extended beyond outflow sides) with
    the scene's initial state: equal masses, or on the lattice of spacing
    ``dx`` with masses ρ dx^d (``masses="lattice"``; ring masses ρ 2π r dx²
    in an axisymmetric scene, whose summation density η starts at m/dx²)."""
    gamma, dim = scene.gamma, scene.dim
    if masses == "lattice":
        x, mass = place_lattice(scene, dx, box)
    else:
        x, mass = (place_1d if dim == 1 else place_2d)(scene, dx, box)
    rho, v, p = initial_state(scene, x, dx)
    n = x.shape[0]
    products = np.zeros(n, bool)
    if scene.detonation is None:
        u = p / ((gamma - 1.0) * rho)
    else:  # (the lattice's masses were the air's: each particle carries its cell's mixture)
        rho, u, products = charged_state(scene, x[:, 0], None if dim == 1 else x[:, 1], dx, rho, p)
        mass = rho * lattice_volumes(scene, x, dx)
    summed = mass / dx ** 2 if scene.geometry == "axisymmetric" else rho
    return Particles(x=x, v=v, u=u, m=np.broadcast_to(mass, n).copy(),
                     H=eta * (mass / summed) ** (1.0 / dim), alpha=np.full(n, alpha_min), alpha_u=np.zeros(n),
                     rho=summed, products=products)


def _entering(inflow, t: float, dt: float, eta: float, mass: float, alpha_min: float) -> Particles:
    """The buffer particles that cross the inlet over ``[t, t + dt]``, as fluid
    particles carrying the boundary state of ``t + dt`` (the layer moved over
    the step)."""
    x = inflow.advance(t, dt)
    _, bv, brho, bu, bH = inflow.particles(t + dt, eta)
    k = x.shape[0]
    if k == 0:
        return Particles(x, np.zeros((0, x.shape[1])), *(np.zeros(0) for _ in range(6)), np.zeros(0, bool))
    return Particles(x=x, v=np.tile(bv[:1], (k, 1)), u=np.full(k, bu[0]), m=np.full(k, mass),
                     H=np.full(k, bH[0]), alpha=np.full(k, alpha_min), alpha_u=np.zeros(k),
                     rho=np.full(k, brho[0]), products=np.zeros(k, bool))


def _buffer(inflow, t: float, eta: float, mass: float):
    """The inflow buffer's particles at time ``t`` as imposed particles
    ``(x, v, rho, u, H, m)`` (each of mass ``mass``), or None without one."""
    if not inflow:
        return None
    bx, bv, brho, bu, bH = inflow.particles(t, eta)
    return bx, bv, brho, bu, bH, np.full(bx.shape[0], mass)


def _observe_inlet(inflow, P: Particles, E: Evaluation, t: float, eta: float) -> None:
    """Give the inflow buffer (if any) the gas within one buffer support of
    the inlet, the downstream state of its boundary Riemann problem."""
    if inflow:
        inflow.observe(P.x, P.v, E.rho, (inflow.scene.gamma - 1.0) * E.rho * P.u, inflow.support(t, eta))


def _inflow_buffer(scene, P: Particles, eta: float):
    """The inflow buffer of the scene's inflow side, or None."""
    sides = [s for s in scene.sides if isinstance(scene.boundaries[s], Inflow)]
    if not sides:
        return None
    rho_in = scene.boundaries[sides[0]].state(scene.t_start)[0]
    depth = SUPPORT_GROWTH * max(P.H.max(), eta * (P.m[0] / rho_in) ** (1.0 / scene.dim)) * 1.5
    return InflowBuffer(scene, sides[0], P.m[0], depth)


def _sample_points(scene) -> np.ndarray:
    """Probe positions, then the midpoint of every side of the domain."""
    dim = scene.dim
    points = [pr.at(dim) for pr in scene.probes]
    for d in range(2 * dim):
        axis, upper = d // 2, d % 2
        mid = [0.5 * (lo + hi) for lo, hi in scene.domain]
        mid[axis] = scene.domain[axis][upper]
        points.append(tuple(mid))
    return np.asarray(points, float)


def _pressure_at(sph, P, E, points) -> np.ndarray:
    """Pressure interpolated at ``points`` (n_points, dim)."""
    p = sph.materials.pressure(sph.gas_density(P.x, E.H, E.rho), P.u, P.products)
    return shepard_at_points(points, P.x, p, P.m / E.rho, E.H, sph.kind, sph.dim, numba.get_num_threads())


def _side_forces(scene, sampled) -> np.ndarray:
    """Pressure force on every side from the pressure sampled at its
    midpoint (per square metre in 1D, times the side's area in 2D and 3D: in
    2D its length per metre depth, or the whole revolved side in r–z)."""
    walls = sampled[len(scene.probes):]
    if scene.dim == 1:
        return walls
    return walls * np.asarray([scene.side_area(side) for side in scene.sides])


class _Run(RunRecord):
    """The record of one SPH run; frames are deposited onto the output grid
    as they are taken."""

    def __init__(self, scene, sph, settings, compile_seconds, history):
        super().__init__(scene, "sph", settings, compile_seconds, history)
        self.sph, self.n_particles, self.reflections = sph, 0, 0
        self.solid = None
        if scene.obstacles:
            X, Y = np.meshgrid(scene.output.x, scene.output.y)
            self.solid = np.any([shape.contains(X, Y) for shape in scene.obstacles], axis=0)

    def closed(self) -> bool:
        """No side lets gas in (particles that leave through an outflow side count as drift)."""
        return not has_inlet(self.scene)

    def totals(self, state) -> dict:
        """Total mass Σm and energy Σ m (u + |v|²/2) of the fluid particles."""
        P = state[0]
        return {"mass": float(P.m.sum()), "energy": float(np.sum(P.m * (P.u + 0.5 * np.sum(P.v * P.v, axis=1))))}

    def fields(self, state) -> dict:
        P, E = state
        scene = self.scene
        rho = self.sph.gas_density(P.x, E.H, E.rho)
        values = {"rho": rho, "u": P.v[:, 0], "p": self.sph.materials.pressure(rho, P.u, P.products), "e": P.u}
        if "Y" in scene.fields:  # the products' mass fraction
            values["Y"] = P.products.astype(float)
        for a, name in enumerate("vw"[: scene.dim - 1], start=1):
            values[name] = P.v[:, a]
        axes = tuple(scene.output.centres(a) for a in range(scene.dim))
        self.n_particles = P.x.shape[0]
        grids = self.sph.interpolate(P, E, np.stack([values[f] for f in scene.fields]), axes)
        if self.solid is not None:
            grids[:, self.solid] = np.nan
        return dict(zip(scene.fields, grids))

    def output(self) -> Output:
        s = self.settings
        fields = {name: self.stacked(name) for name in self.scene.fields}
        scheme = (f"grad-h SPH ({s['kernel']}, H = {s['eta']:g} (m/rho)^(1/d)), Cullen-Dehnen viscosity "
                  f"(alpha_max {s['alpha_max']:g}), artificial conduction with its switch (alpha_u_max {s['alpha_u']:g}), "
                  "predictor-corrector leapfrog, mirror-particle plane walls"
                  + (", skew-gradient obstacle walls (wall + virtual particles, slip)" if self.solid is not None else "")
                  + (", axisymmetric: ring masses on the r-z lattice, mirror ghosts across the axis, the density "
                     "eta / (2 pi (r + 2 H J(r/H))) near it and the hoop terms (Garcia-Senz et al. 2009)"
                     if self.sph.axisymmetric else "")
                  + (f", two materials: air and {self.sph.materials.explosive.name} detonation products (JWL) on the "
                     "particles that carry them" if self.sph.materials.explosive is not None else ""))
        attrs = {"deposition": "Shepard (kernel-normalised) interpolation with the particles' own kernel and H",
                 "wall_reflections": self.reflections, "force_interactions": self.sph.force_interactions,
                 "neighbour_searches": self.sph.counters[1],
                 **{f"seconds_{name}": seconds for name, seconds in self.sph.counters[0].items()}}
        return Output(fields, self.solid, scheme, self.n_particles, attrs)
