"""The gas SPH scheme (SPEC §3.1), apart from the run that drives it: the
particle state (:class:`Particles`), what one evaluation of it gives
(:class:`Evaluation`), and :class:`GasSPH`, the equations of one run bound
to its scene: summation density with adaptive support and grad-h terms
(:mod:`~partmesh.particle.sph.density`), variational momentum and energy
with Cullen–Dehnen viscosity and artificial conduction
(:mod:`~partmesh.particle.sph.forces`), the walls' virtual particles, the
reused neighbour lists, and Shepard interpolation onto a grid (Price 2012,
J. Comput. Phys. 231, 759; Prasanna Kumar, Patnaik & Ramamurthi 2018,
Phys. Fluids 30, 046105). In an axisymmetric scene the particles carry
ring masses and the same sums give η, the mass per area of the r–z plane,
with the axis factors and hoop terms of :mod:`~partmesh.particle.sph.axis`
(García-Senz et al. 2009). The method ``sph`` (:mod:`~partmesh.particle.sph.solve`)
and the particles of ``hybrid`` both step it."""

from __future__ import annotations

import dataclasses
import time as _time
from dataclasses import dataclass

import numba
import numpy as np

from partmesh.particle import kernels
from partmesh.particle.neighbours import neighbour_lists
from partmesh.particle.pair_geometry import padded
from partmesh.particle.sph.axis import axis_density, axis_factors
from partmesh.particle.sph.density import density_and_support
from partmesh.particle.sph.forces import rates
from partmesh.particle.sph.integrator import SEARCH_SLACK
from partmesh.particle.sph.lists import PerParticle, VerletLists
from partmesh.particle.sph.materials import Materials
from partmesh.particle.sph.method import has_inlet
from partmesh.particle.sph.sampling import on_grid
from partmesh.particle.sph.wall_placement import in_box
from partmesh.particle.sph.wall_state import virtual_state

#: output cells whose kernel sum Σ V W is below this fraction of full support are NaN (no fluid)
MIN_SUPPORT = 1e-3


@dataclass
class Particles(PerParticle):
    """The fluid particles of a run (ghosts are rebuilt every evaluation);
    ``rho`` is the summation density of the last evaluation, which the
    walls' virtual particles are extrapolated from. In an axisymmetric
    scene ``m`` are ring masses and ``rho`` is η, the mass per area of the
    r–z plane (:meth:`GasSPH.gas_density` gives ρ). ``products`` is True for
    the particles of detonation products (:mod:`~partmesh.particle.sph.materials`)."""

    x: np.ndarray
    v: np.ndarray
    u: np.ndarray
    m: np.ndarray
    H: np.ndarray
    alpha: np.ndarray
    alpha_u: np.ndarray
    rho: np.ndarray
    products: np.ndarray

    def keep(self, mask):
        """Drop the particles where ``mask`` is False."""
        for f in dataclasses.fields(self):
            setattr(self, f.name, getattr(self, f.name)[mask])

    def append(self, other: "Particles"):
        """Add the particles of ``other`` after these."""
        for f in dataclasses.fields(self):
            setattr(self, f.name, np.concatenate([getattr(self, f.name), getattr(other, f.name)]))


@dataclass
class Evaluation(PerParticle):
    """Everything computed from one particle state (fluid particles only);
    ``rho`` as in :class:`Particles`, ``div_v`` the gas's ∇·v."""

    rho: np.ndarray
    H: np.ndarray
    dvdt: np.ndarray
    dudt: np.ndarray
    div_v: np.ndarray
    curl_v: np.ndarray
    vsig: np.ndarray
    lap_u: np.ndarray


class GasSPH:
    """The SPH equations of one run, bound to its scene and settings."""

    def __init__(self, scene, kernel: str, eta: float, region, open_=(), wall=None):
        self.scene, self.kernel, self.eta = scene, kernel, eta
        self.region, self.wall = region, wall
        #: wall seconds spent in the density and force passes, and the interactions the force pass
        #: summed (ordered pairs i fluid, r_ij < max(H_i, H_j)), over the run
        self.seconds = dict.fromkeys(("density", "forces"), 0.0)
        self.force_interactions = 0
        self.kind = kernels.KERNELS[kernel]
        self.materials = Materials.of(scene)
        self.dim = scene.dim
        self.axisymmetric = scene.geometry == "axisymmetric"
        self.lo = np.array([lo for lo, _ in scene.domain])
        self.hi = np.array([hi for _, hi in scene.domain])
        self.periodic = np.array(scene.periodic)
        #: the neighbour lists, reused while they hold every pair (and the periods of the box)
        self.verlet = VerletLists(scene, self.lo, self.hi, self.periodic, open_)

    @property
    def counters(self) -> tuple:
        """``(seconds per pass, searches, force interactions)`` of the run so far."""
        return {"search": self.verlet.seconds, **self.seconds}, self.verlet.searches, self.force_interactions

    @counters.setter
    def counters(self, value):
        seconds, self.verlet.searches, self.force_interactions = value
        self.verlet.seconds = seconds["search"]
        self.seconds = {k: seconds[k] for k in self.seconds}

    def retained(self, x) -> np.ndarray | None:
        """True for the particles still in the run: within the particle box
        (not out through an outflow side, nor pushed back upstream of the
        inlet); None where none can leave (no outflow side, no inlet: the
        walls keep every particle in)."""
        if not self.verlet.open and not has_inlet(self.scene):
            return None
        return in_box(x, self.region)

    def evaluate(self, P: Particles, x, v, u, imposed=None, growth=None) -> Evaluation:
        """Density, support and rates of change of the fluid particles at the
        state ``(x, v, u)``; ``P`` supplies masses, the support guess, the
        viscosity and conduction switches and the last density; ``growth``,
        the supports' expected growth over the next few steps, widens the
        lists of a new search (:meth:`VerletLists.search`). Particles whose state is
        imposed, not computed — ``imposed`` ``(x, v, rho, u, H, m)`` (an inflow
        buffer, the boundary particles of ``hybrid``) and the walls' virtual
        particles — act as neighbours only; mirror ghosts are made of all of them."""
        n, dim, gamma = x.shape[0], self.dim, self.scene.gamma
        given = [(np.zeros((0, dim)), np.zeros((0, dim)), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0))]
        if imposed is not None:
            given.append(imposed)
        if self.wall is not None:
            given.append(virtual_state(self.wall, x, v, P.rho, (gamma - 1.0) * P.rho * u, P.m, P.H, self.kind,
                                         self.eta, gamma))
        bx, bv, brho, bu, bH, bm = (np.concatenate(parts) for parts in zip(*given))
        x_real, v_real = np.concatenate([x, bx]), np.concatenate([v, bv])
        H_real = np.concatenate([P.H, bH])
        m_real = np.concatenate([P.m, bm])
        lists = self.verlet.reusable(x_real, v_real, H_real, n)
        slack = SEARCH_SLACK
        for _ in range(5):
            if lists is None:
                lists = self.verlet.search(x_real, v_real, H_real, n, slack, growth)
                slack *= 1.4  # for the next search, if a solution reaches the edge of these lists
            src, offsets, index = lists.src, lists.offsets, lists.index
            # a ghost's ring mass (and η, P) is its source's at the ghost's own radius (axis.py)
            ring = self.ghost_rings(x_real, lists) if self.axisymmetric else None
            m = np.concatenate([m_real, m_real[src] if ring is None else m_real[src] * ring])
            X3 = padded(lists.x)
            t0 = _time.perf_counter()
            rho, H, omega, converged = density_and_support(X3, self.verlet.box, self.verlet.half, m,
                                                           np.concatenate([H_real, H_real[src]]), lists.radius,
                                                           offsets, index, self.kind, dim, self.eta, n)
            self.seconds["density"] += _time.perf_counter() - t0
            failed = ~converged | (H >= (1.0 - 1e-6) * lists.radius[:n])
            if not failed.any():
                break
            radius, lists = lists.radius, None
        else:
            k = int(np.flatnonzero(failed)[0])
            if radius[k] >= (1.0 - 1e-6) * self.verlet.half_period:
                raise FloatingPointError(f"the support H of the particle at x = {x[k].tolist()} m reached half the "
                                         f"periodic width ({self.verlet.half_period:g} m): run a wider domain "
                                         "(one_period=false) or a finer dx")
            raise FloatingPointError(f"the smoothing-length iteration did not converge at x = {x[k].tolist()}")
        real = [np.concatenate([a, b]) for a, b in ((rho, brho), (H, bH), (omega, np.ones(bx.shape[0])),
                                                    (u, bu), (P.alpha, np.zeros(bx.shape[0])),
                                                    (P.alpha_u, np.zeros(bx.shape[0])))]
        rho_all, H_all, omega_all, u_all, alpha_all, alpha_u_all = (np.concatenate([a, a[src]]) for a in real)
        if ring is not None:
            rho_all[x_real.shape[0]:] *= ring
        p = (gamma - 1.0) * rho_all * u_all
        held = None
        with np.errstate(invalid="ignore"):  # a negative energy: NaN rates, which the step reports with where
            if self.materials.holds_products(P.products):  # P = η p/ρ (a ghost's p/ρ its source's)
                held, per_density, c_held = self.products_state(P.products, x_real, rho, H, u, src)
                p[held] = rho_all[held] * per_density[held]
            if self.axisymmetric:  # P = (γ − 1) η u, times Φ (axis.py)
                axis = axis_factors(x_real[:, 0], real[1], self.kind)
                p *= np.concatenate([axis.grad_h, axis.grad_h[src]])
                c = np.sqrt(gamma * (gamma - 1.0) * u_all)
            else:
                c = np.sqrt(gamma * p / rho_all)
        if held is not None:
            c[held] = c_held[held]
        t0 = _time.perf_counter()
        *derived, interactions = rates(X3, self.verlet.box, self.verlet.half, lists.v, m, u_all, rho_all, p, c,
                                       omega_all, H_all, alpha_all, alpha_u_all, offsets, index, self.kind, dim, n,
                                       numba.get_num_threads())
        E = Evaluation(rho, H, *derived)
        if self.axisymmetric:
            p_over_rho = (gamma - 1.0) * u
            if held is not None:
                p_over_rho[P.products] = per_density[:n][P.products]
            _add_hoop_terms(E, axis, v[:, 0], p_over_rho)
        self.seconds["forces"] += _time.perf_counter() - t0
        self.force_interactions += int(interactions)
        return E

    def products_state(self, products, x_real, rho, H, u, src) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(held, p/ρ, c)`` over the fluid, imposed and ghost particles of one evaluation: the mask of those
        holding detonation products (a ghost its source's), their pressure per gas density and sound speed
        from the JWL equation of state at their gas density (:meth:`gas_density` of the summation density
        ``rho`` and support ``H`` of the fluid particles at ``x_real``, energy ``u``), zero elsewhere."""
        n, total = products.shape[0], x_real.shape[0]
        k = np.flatnonzero(products)
        per_density, c = np.zeros(total), np.zeros(total)
        per_density[k], c[k] = self.materials.products_state(self.gas_density(x_real[k], H[k], rho[k]), u[k])
        held = np.zeros(total, bool)
        held[:n] = products
        return tuple(np.concatenate([a, a[src]]) for a in (held, per_density, c))

    @staticmethod
    def ghost_rings(x_real, lists) -> np.ndarray:
        """The ratio of each mirror ghost's radius to its source's, |r_g|/r_s:
        1 across the axis and along r, r_g/r_s beyond an outer side, where a
        ghost stands for the ring at its own radius so that a uniform gas
        stays uniform up to the wall (1 for a source on the axis itself)."""
        r_src = x_real[lists.src, 0]
        r_ghost = np.abs(lists.x[x_real.shape[0]:, 0])
        return np.divide(r_ghost, r_src, out=np.ones_like(r_src), where=r_src > 0.0)

    def gas_density(self, x, H, rho) -> np.ndarray:
        """The gas density ρ of particles at ``x`` with support ``H`` and
        summation density ``rho``: ``rho`` itself in a planar scene, η/(2π r̃)
        in an axisymmetric one (:func:`~partmesh.particle.sph.axis.axis_density`)."""
        return axis_density(rho, x[:, 0], H, self.kind) if self.axisymmetric else rho

    def compile_rest(self, P: Particles, E: Evaluation) -> None:
        """Compile (or load) the kernels a run meets after its first
        evaluation, so that its time excludes them: the lists' renumbering,
        a frame's deposition, a search among a few much wider particles."""
        self.verlet.renumber(np.arange(P.x.shape[0]))
        axes = tuple(np.linspace(lo, hi, 3) for lo, hi in zip(self.lo, self.hi))
        self.interpolate(P, E, P.u[None, :], axes)
        x = self.lo + (self.hi - self.lo) * np.linspace(0.05, 0.95, 40)[:, None]
        H = np.full(40, 0.02 * float(np.min(self.hi - self.lo)))
        H[0] *= 4.0  # (wider than 1.25 times the 95th percentile: searched apart)
        neighbour_lists(x, H, self.lo, self.hi, self.periodic)

    def interpolate(self, P: Particles, E: Evaluation, values, axes):
        """Shepard interpolation of particle ``values`` (k, n) on the uniform
        grid with cell-centre ``axes`` (x[, y[, z]]): the schema layout (k, [z, [y,]] x)."""
        return on_grid(P.x, values, P.m / E.rho, E.H, axes, self.periodic, self.kind, MIN_SUPPORT, self.hi - self.lo)


def _add_hoop_terms(E: Evaluation, axis, v_r, per_density) -> None:
    """Add to the planar rates ``E`` of η and ΦP what the axis adds
    (:mod:`~partmesh.particle.sph.axis`): the hoop acceleration (p/ρ) r̃'/r̃
    along r, its work −(p/ρ) r̃' v_r/r̃ in du/dt, and ∇·v = Φ ∇₂·v + r̃' v_r/r̃
    (``per_density`` p/ρ of the fluid particles, (γ − 1)u in air; the first
    ``len(per_density)`` entries of ``axis`` are the fluid particles')."""
    n = per_density.shape[0]
    hoop = per_density * axis.slope[:n] / axis.radius[:n]
    E.dvdt[:, 0] += hoop
    E.dudt -= hoop * v_r
    E.div_v = axis.grad_h[:n] * E.div_v + axis.slope[:n] * v_r / axis.radius[:n]
