"""Water SPH (method ``wcsph``): run a planar water scene as a vertical
(x, z) slice of weakly compressible SPH and return a schema Dataset on the
scene's output grid (SPEC §3.2; Monaghan 1994, J. Comput. Phys. 110, 399;
Crespo et al. 2015, Comput. Phys. Commun. 187, 204).

Time integration is the velocity Verlet (kick–drift–kick) leapfrog with a
predicted velocity and density for the rates (as the gas SPH's,
:mod:`partmesh.particle.sph.solve`), one evaluation per step:

    v^{n+½} = v^n + ½Δt a^n,  ρ^{n+½} = ρ^n + ½Δt D^n,  x^{n+1} = x^n + Δt v^{n+½},
    (a, D)^{n+1} = rates(x^{n+1}, v^n + Δt a^n, ρ^n + Δt D^n),
    v^{n+1} = v^{n+½} + ½Δt a^{n+1},  ρ^{n+1} = ρ^{n+½} + ½Δt D^{n+1},

at Δt = C min_a min(h/(c_a + max_b |μ_ab|), sqrt(h/|a_a|)), C = 0.2
(Monaghan 1992; Crespo et al. 2015 eq. 23). Walls are mirror particles
(free slip; below the bed their pressure carries the hydrostatic increment
ρ g Δz, so the water rests on the bed without a gap). The output fields
are depth-integrated: ``h`` the water column (Σ_b V_b W_1(x − x_b), a 1D
kernel sum over the particles' x), ``eta`` = bed + ``h``, ``u`` the
column's mean horizontal velocity; the gauges sample ``eta`` the same way.
"""

from __future__ import annotations

import math
import time as _time
from dataclasses import dataclass

import numba
import numpy as np

from partmesh.cases.checkpoint import checkpoint_for
from partmesh.cases.compiling import compiling
from partmesh.cases.history import History, Output, RunRecord
from partmesh.cases.march import StepFailed, landed
from partmesh.compare.io import particle_snapshot
from partmesh.particle import kernels
from partmesh.particle.cell_grid import sort_order
from partmesh.particle.march import march_particles
from partmesh.particle.pair_geometry import padded
from partmesh.particle.sph.lists import PerParticle, VerletLists
from partmesh.particle.sph.particles import mirror_ghosts, reflect_at_plane_walls
from partmesh.particle.sph.sampling import kernel_sums_at_points, kernel_sums_on_grid
from partmesh.particle.wcsph.eos import Tait
from partmesh.particle.wcsph.flume import damping_rate, flume, water_at_rest
from partmesh.particle.wcsph.method import WCSPHSettings
from partmesh.particle.wcsph.rates import dynamic_density_gradients, rates

#: the kernel (SPEC §3.2: quintic Wendland, W ∝ (1 − q/2)^4 (2q + 1) for q = r/h ≤ 2)
KERNEL = "wendland_c2"
#: the lists are searched for this multiple of the support (the skin lets them serve a few steps)
SEARCH_SLACK = 1.2
#: the particle arrays are re-sorted along the search cells every so many steps
RESORT_STEPS = 20
#: the 1D kernel of the column sums and its support in units of dx: the sum of
#: dx W_1(x − x_j) over a row of particles dx apart departs from 1 by at most
#: 7e-6 (Wendland C2 at 4 dx: 2e-3, i.e. a millimetre of surface)
COLUMN_KERNEL, COLUMN_SUPPORT = "wendland_c4", 8.0
#: a column holding less water than this fraction of dx is dry (eta NaN, u 0)
DRY_FRACTION = 0.25
KINDS = {"fluid": 0}


@dataclass
class Particles(PerParticle):
    """The water particles of a run (their mirror ghosts are made anew at
    every evaluation)."""

    x: np.ndarray
    v: np.ndarray
    rho: np.ndarray
    m: np.ndarray


@dataclass
class Evaluation(PerParticle):
    """Rates of the particles at one state: acceleration (gravity
    included), density rate, largest |μ| each particle sees."""

    dvdt: np.ndarray
    drhodt: np.ndarray
    mu_max: np.ndarray


class WaterSPH:
    """The water SPH equations of one run, bound to its scene and flume."""

    def __init__(self, scene, slice_, eos: Tait, dx: float, H: float, alpha: float, delta: float):
        self.scene, self.flume, self.eos, self.dx, self.H = scene, slice_, eos, dx, H
        self.alpha, self.delta = alpha, delta
        self.kind, self.column_kind = kernels.KERNELS[KERNEL], kernels.KERNELS[COLUMN_KERNEL]
        (x0, x1), (z0, z1) = slice_.domain
        self.lo, self.hi = np.array([x0, z0]), np.array([x1, z1])
        self.verlet = VerletLists(slice_, self.lo, self.hi, slice_.periodic)
        #: wall seconds of the rates pass and the pairs it summed, over the run
        self.seconds_rates, self.interactions = 0.0, 0

    @property
    def counters(self) -> tuple:
        """``(seconds of the rates pass, pairs summed, seconds of the lists, searches)`` of the run so far."""
        return self.seconds_rates, self.interactions, self.verlet.seconds, self.verlet.searches

    @counters.setter
    def counters(self, value):
        self.seconds_rates, self.interactions, self.verlet.seconds, self.verlet.searches = value

    def hydrostatic_density(self, z):
        """ρ_H(z): the density of water at rest under the still surface η = 0."""
        return self.eos.density(self.eos.hydrostatic_pressure(-z, self.scene.g))

    def evaluate(self, x, v, rho, m) -> Evaluation:
        """Rates of the particles at positions ``x``, velocities ``v`` and
        densities ``rho``; their mirror ghosts carry the source's density
        at the source's pressure plus ρ g (z_source − z_ghost)."""
        n, g = x.shape[0], self.scene.g
        lists = self.verlet.lists(x, v, np.full(n, self.H), n, SEARCH_SLACK)
        src = lists.src
        p = self.eos.pressure(rho)
        z_ghost = lists.x[n:, 1]
        p_ghost = p[src] + rho[src] * g * (x[src, 1] - z_ghost)
        rho_all = np.concatenate([rho, self.eos.density(p_ghost)])
        p_all = np.concatenate([p, p_ghost])
        m_all = np.concatenate([m, m[src]])
        rho_dynamic = rho_all - self.hydrostatic_density(lists.x[:, 1])
        X3, box, half, threads = padded(lists.x), self.verlet.box, self.verlet.half, numba.get_num_threads()
        t0 = _time.perf_counter()
        G = np.zeros((lists.x.shape[0], 3))
        if self.delta > 0.0:
            G[:n, :2] = dynamic_density_gradients(X3, box, half, m_all / rho_all, rho_dynamic, self.H,
                                                  lists.offsets, lists.index, self.kind, n, threads)
            # a ghost's ρ^D mirrors its source's: the gradient's normal components flip
            G[n:] = G[src]
            for bit in range(len(self.flume.sides)):
                G[n:, bit // 2] *= np.where(lists.sides & (1 << bit), -1.0, 1.0)
        dvdt, drhodt, mu_max, pairs = rates(X3, box, half, padded(lists.v), m_all, rho_all, p_all,
                                            self.eos.sound_speed(rho_all), rho_dynamic, G, self.H, self.eos.c0,
                                            self.alpha, self.delta, lists.offsets, lists.index, self.kind, 2, n,
                                            threads)
        self.seconds_rates += _time.perf_counter() - t0
        self.interactions += int(pairs)
        dvdt[:, 1] -= g
        return Evaluation(dvdt, drhodt, mu_max)

    def stable_dt(self, P: Particles, E: Evaluation, cfl: float) -> float:
        """C min(h/(c + max|μ|), sqrt(h/|a|)) over the particles."""
        h = 0.5 * self.H
        acoustic = h / (self.eos.sound_speed(P.rho) + E.mu_max)
        force = np.sqrt(h / np.maximum(np.linalg.norm(E.dvdt, axis=1), 1e-300))
        return cfl * float(min(acoustic.min(), force.min()))

    def retained(self, x) -> np.ndarray:
        """True for the particles still in the flume (not out through an
        outflow side)."""
        (x0, x1), _ = self.flume.domain
        keep = np.ones(x.shape[0], bool)
        if self.flume.boundaries["x_lo"] == "outflow":
            keep &= x[:, 0] >= x0
        if self.flume.boundaries["x_hi"] == "outflow":
            keep &= x[:, 0] <= x1
        return keep

    def columns(self, P: Particles, points=None):
        """``(h, u)``: the water column Σ_b V_b W_1(x − x_b) (W_1: the 1D
        :data:`COLUMN_KERNEL`) and its mean horizontal velocity, at the
        output grid's x (``points`` None) or at the x of ``points``; the
        particles' mirror images across the x walls complete the sums next
        to them."""
        support = COLUMN_SUPPORT * self.dx
        gx, gv, src, _ = mirror_ghosts(self.flume.without_bed(), P.x, P.v, support, ())
        x = np.ascontiguousarray(np.concatenate([P.x[:, 0], gx[:, 0]]))
        volume = np.concatenate([P.m / P.rho, (P.m / P.rho)[src]])
        u = np.concatenate([P.v[:, 0], gv[:, 0]])[None, :]
        H = np.full(x.size, support)
        if points is None:
            out = self.scene.output.x
            num, den = kernel_sums_on_grid(x, np.zeros(x.size), np.zeros(x.size), u, volume, H, out[0],
                                           out[1] - out[0], out.size, 0.0, 1.0, 1, 0.0, 1.0, 1,
                                           np.array([self.flume.periodic[0], False, False]), self.column_kind, 1)
            num, den = num[0, 0, 0], den[0, 0]
        else:
            num, den = kernel_sums_at_points(np.asarray(points, float).reshape(-1, 1), x[:, None], u, volume, H,
                                             self.column_kind, 1, numba.get_num_threads())
            num = num[0]
        wet = den >= DRY_FRACTION * self.dx
        return den, np.where(wet, num / np.where(wet, den, 1.0), 0.0)

    def energy(self, P: Particles) -> float:
        """Total energy per unit width [J/m]: kinetic, potential m g z and
        the internal energy the Tait pressure stores (:meth:`Tait.internal_energy`)."""
        e = self.eos.internal_energy(P.rho)
        return float(np.sum(P.m * (0.5 * np.sum(P.v * P.v, axis=1) + self.scene.g * P.x[:, 1] + e)))


def solve(scene, settings: WCSPHSettings):
    """Run the planar water ``scene`` with weakly compressible SPH in a
    vertical slice and checked ``settings``
    (:class:`~partmesh.particle.wcsph.method.WCSPHSettings`).

    Raises :class:`~partmesh.cases.errors.SolverFailed` with the partial result if
    the state turns non-physical or the run is interrupted. Checkpoints as
    in the other methods (:mod:`partmesh.cases.checkpoint`; the neighbour lists are
    searched anew after a resume, which changes the summation order only).
    """
    dx, cfl = settings.dx, settings.cfl
    slice_ = flume(scene, dx, settings.damping)
    record = {**settings.record(), "damping": slice_.damping}
    deepest = float(np.max(np.asarray(scene.initial(scene.output.x, None)[0], float) - slice_.bed))
    eos = Tait(scene.rho, settings.c0 * math.sqrt(scene.g * max(deepest, scene.depth)))
    x, v, rho, m = water_at_rest(scene, slice_, dx, eos)
    P = Particles(x, v, rho, m)
    sph = WaterSPH(scene, slice_, eos, dx, settings.eta * dx, settings.alpha, settings.delta)
    sigma = lambda x: damping_rate(slice_, x, scene.g, scene.depth)  # noqa: E731
    gauges = np.array([pr.x for pr in scene.probes] or [scene.output.x[0]])
    with compiling("wcsph", settings.progress) as compiled:
        E = sph.evaluate(P.x, P.v, P.rho, P.m)  # compiles (or loads) the kernels, as do the sums below
        h_gauges, _ = sph.columns(P, gauges)
        sph.columns(P)
    compile_seconds = compiled.seconds
    sph.counters = 0.0, 0, 0.0, 0
    run = _Run(scene, sph, record, compile_seconds, History(h_gauges + slice_.bed, 2))
    run.energies.append((0.0, sph.energy(P)))
    t = 0.0
    ckpt = checkpoint_for(scene, settings)
    saved = ckpt.saved_state(run)
    if saved is not None:
        P, E, t = saved["P"], saved["E"], saved["t"]
        sph.counters = saved["counters"]
    no_forces = np.zeros(2)

    def step(state, t, dt_cfl, t_out):
        P, E = state
        if run.n_steps % RESORT_STEPS == 0:
            order = sort_order(P.x, sph.lo, sph.hi, 0.5 * sph.H)
            P, E = P.take(order), E.take(order)
            sph.verlet.renumber(order)
        dt_stable = sph.stable_dt(P, E, cfl)
        dt = min(dt_stable, t_out - t)
        v_half, rho_half = P.v + 0.5 * dt * E.dvdt, P.rho + 0.5 * dt * E.drhodt
        v_pred, rho_pred = P.v + dt * E.dvdt, P.rho + dt * E.drhodt
        x_new = sph.verlet.wrapped(P.x + dt * v_half)
        x_new, v_half, v_pred, reflected = reflect_at_plane_walls(slice_, x_new, v_half, v_pred)
        run.reflections += reflected
        stay = sph.retained(x_new)
        Q = Particles(x_new, v_half, rho_half, P.m)
        if not stay.all():
            Q, v_pred, rho_pred = Q.take(stay), v_pred[stay], rho_pred[stay]
        E_new = sph.evaluate(Q.x, v_pred, rho_pred, Q.m)
        Q.v = (Q.v + 0.5 * dt * E_new.dvdt) / (1.0 + dt * sigma(Q.x))[:, None]
        Q.rho = Q.rho + 0.5 * dt * E_new.drhodt
        if not (np.all(np.isfinite(Q.v)) and np.all(Q.rho > 0.0)):
            k = int(np.flatnonzero(~(Q.rho > 0.0) | ~np.isfinite(Q.v).all(axis=1))[0])
            raise StepFailed(f"wcsph became unstable at t = {t + dt:.6g} s (step {run.n_steps + 1}): density "
                             f"{Q.rho[k]:.4g} kg m-3, velocity {Q.v[k].round(4).tolist()} m/s at (x, z) = "
                             f"{Q.x[k].round(4).tolist()} m; lower cfl (now {cfl:g}).")
        t_new = landed(t, dt, t_out)
        if t_new < run.history.t[-1] + scene.output.dt_probe * (1 - 1e-9) and t_new != t_out:
            return (Q, E_new), dt, dt_stable, None
        h_gauges, _ = sph.columns(Q, gauges)
        run.energies.append((t_new, sph.energy(Q)))
        return (Q, E_new), dt, dt_stable, ((h_gauges + slice_.bed)[: len(scene.probes)], no_forces)

    def saved_state(state, t, dt_cfl):
        P, E = state
        return {"P": P, "E": E, "t": t, "counters": sph.counters}

    return march_particles(run, (P, E), t, step, ckpt, saved_state, settings, P.x.shape[0],
                           lambda state, t: _snapshot(sph, state[0], t))


def _snapshot(sph: WaterSPH, P: Particles, t: float):
    """The water particles at time ``t`` (SPEC §2; y is the height z)."""
    return particle_snapshot(P.x, P.v, P.rho, sph.eos.pressure(P.rho), P.m, np.full(P.rho.size, sph.H),
                             np.zeros(P.rho.size, np.int8), KINDS, sph.scene.name, "wcsph", t, mass_units="kg m-1")


class _Run(RunRecord):
    """The record of one wcsph run: frames are the depth-integrated fields
    on the output grid; ``energies`` the ``(t, total energy)`` at the start
    and at every gauge sample."""

    def __init__(self, scene, sph: WaterSPH, settings, compile_seconds, history):
        super().__init__(scene, "wcsph", settings, compile_seconds, history)
        self.sph, self.reflections, self.energies, self.n_particles = sph, 0, [], 0

    def fields(self, state) -> dict:
        P = state[0]
        h, u = self.sph.columns(P)
        self.n_particles = P.x.shape[0]
        wet = h >= DRY_FRACTION * self.sph.dx
        values = {"eta": np.where(wet, h + self.sph.flume.bed, np.nan), "u": u, "h": h}
        return {name: values[name] for name in self.scene.fields}

    def saved(self) -> dict:
        return {**super().saved(), "reflections": self.reflections, "energies": self.energies}

    def restore(self, saved: dict) -> None:
        super().restore(saved)
        self.reflections, self.energies = saved["reflections"], saved["energies"]

    def output(self) -> Output:
        s, sph = self.settings, self.sph
        fields = {name: self.stacked(name) for name in self.scene.fields}
        scheme = (f"weakly compressible SPH in the (x, z) slice: Tait EOS (c0 = {sph.eos.c0:.4g} m/s), quintic "
                  f"Wendland kernel (h = {0.5 * s['eta']:.4g} dx), Monaghan viscosity (alpha {s['alpha']:g}), "
                  f"delta-SPH density diffusion of the departure from hydrostatic density (delta {s['delta']:g}), "
                  f"velocity Verlet at CFL {s['cfl']:g}, mirror-particle walls"
                  + (f", damping zone {s['damping']:g} m" if s["damping"] else ""))
        attrs = {"deposition": "depth-integrated: h = sum V W_1(x - x_b), u its mean horizontal velocity",
                 "wall_reflections": self.reflections, "force_interactions": sph.interactions,
                 "neighbour_searches": sph.verlet.searches, "seconds_search": sph.verlet.seconds,
                 "seconds_forces": sph.seconds_rates, "sound_speed": sph.eos.c0,
                 "total_energy": np.array([e for _, e in self.energies]),
                 "total_energy_time": np.array([t for t, _ in self.energies]),
                 "long_names": {"u": "depth-averaged velocity x"}}
        return Output(fields, None, scheme, self.n_particles, attrs)
