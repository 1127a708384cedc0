"""One unsplit MUSCL–Hancock step for the Euler equations (van Leer 1984;
Toro 2009 §14.4; multi-dimensional unsplit form as in Colella 1990 without
transverse Riemann solves).

1. limited primitive slopes ``ΔW_d`` along every direction;
2. predictor ``W^{n+1/2} = W − (Δt/2) Σ_d A_d(W) ΔW_d / Δx_d`` with the
   primitive-variable Jacobians ``A_d``;
3. face states ``W^{n+1/2} ± ΔW_d/2``; a cell whose face states are not
   physical (ρ ≤ 0 or p ≤ 0) falls back to first order (zero slope, no
   predictor) — the positivity fallback;
4. a Riemann flux per face, ``U^{n+1} = U − Δt Σ_d (F_{d,i+1/2} − F_{d,i−1/2})/Δx_d``
   (around obstacles the cut-cell form of :mod:`partmesh.gridref.euler.immersed`).

Sums over directions are formed before they are applied, so the update is
exactly symmetric under exchanging x and y on a square grid.

In a geometry of revolution (``Scheme.radial`` = k, x the radius) the
predictor adds the geometric terms ``−g ρ u_r`` and ``−g γ p u_r``, the
radial faces' fluxes are weighted by their areas and their difference
divided by the cell's volume, and the radial momentum gains the hoop
source ``p^{n+1/2} g`` (:mod:`partmesh.gridref.revolution`).

The step is a short pipeline of separately jitted kernels (ghost cells,
slopes, predictor, one flux kernel per direction, update). Each kernel's
outputs are materialised between kernels: as one program, XLA:CPU fuses the
predictor into every flux consumer and recomputes it many times over (an
order of magnitude slower, measured with ``partmesh bench``).

A 2D or 3D grid without bodies is stepped in strips of rows or planes (:func:`strip_attempt`):
the pipeline runs on one strip, then the next, so that its materialised
arrays stay in the processor's caches (2048² Sedov: 3.2e6 cell updates/s
whole, 1.1e7 in strips; 512²: 9.5e6 and 1.4e7).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.gridref.device_loop import device_loop
from partmesh.gridref.euler.boundaries import N_GHOST, SchemeAxes, with_ghosts
from partmesh.gridref.euler.mixture import burnt
from partmesh.gridref.euler.reconstruct import LIMITERS, limited_slopes
from partmesh.gridref.euler.riemann import RIEMANN_SOLVERS
from partmesh.gridref.euler.state import (density_scalars, first_scalar, internal_energy, parts, primitive, rotated,
                                          scalar_count, sound_speed, stiffness)
from partmesh.gridref.grid import cropped
from partmesh.gridref.revolution import REVOLUTION, RadialTable, Rings, revolved
from partmesh.gridref.staging import staged


def _shifted(a, axis, lo):
    """Cells ``[0, n-1)`` (``lo=True``) or ``[1, n)`` along ``axis``: the two
    sides of every interior face."""
    index = [slice(None)] * a.ndim
    index[axis] = slice(0, -1) if lo else slice(1, None)
    return a[tuple(index)]


def primitive_change(W, dW, d, gas):
    """``A_d(W) ΔW``: the quasi-linear primitive Euler operator along ``d``,
    ``(u_n Δρ + ρ Δu_n, u_n Δu_k + δ_kd Δp/ρ, u_n Δp + ρc² Δu_n)`` (``ρc² = γp``
    for an ideal gas); a mixture's partial densities q change like ρ,
    ``u_n Δq + q Δu_n``, its volume fraction by ``u_n Δα``."""
    rho, un = W[0], W[1 + d]
    dun, dp = dW[1 + d], dW[-1]
    dvel = [un * dv for dv in dW[1:-1]]
    dvel[d] = dvel[d] + dp / rho
    for k in density_scalars(W, gas):  # (dvel holds W[1:-1])
        dvel[k - 1] = dvel[k - 1] + W[k] * dun
    return (un * dW[0] + rho * dun, *dvel, un * dp + stiffness(W, gas) * dun)


def stable_dt(U, gas, dx, cfl, fluid=None, crowding=None):
    """CFL time step ``Δt = C / max_cells Σ_d (|u_d| + c)/Δx_d``; NaN if the
    fluid holds NaN, negative density or negative pressure (the caller
    reports where). In a geometry of revolution the radial rate of a cell
    is raised by its ``crowding``, the ratio of its faces' mean area to its
    volume, ``max(1, (a_{i−1/2} + a_{i+1/2}) / (2 v_i))``
    (:class:`partmesh.gridref.revolution.Rings`): 1.5 at a sphere's centre,
    where a step of C = 0.8 is unstable, and 1 in every cell of a cylinder
    (k = 1)."""
    W = primitive(U, gas)
    c = sound_speed(W, gas)
    rate = sum((jnp.abs(W[1 + d]) + c) * (1.0 / dx[d]) for d in range(len(dx)))
    if crowding is not None:
        rate = rate + (jnp.abs(W[1]) + c) * ((crowding - 1.0) / dx[0])
    bad = ~(W[0] > 0.0) | ~(W[-1] > 0.0) | ~jnp.isfinite(rate)
    if fluid is not None:
        rate = jnp.where(fluid, rate, 0.0)
        bad = bad & fluid
    return jnp.where(jnp.any(bad), jnp.nan, cfl / jnp.max(rate))


@dataclass(frozen=True)
class Scheme(SchemeAxes):
    """Settings of the MUSCL–Hancock scheme: ``gamma`` the gas's ratio of
    specific heats, or with ``mixture`` the air's beside detonation products."""

    gamma: float
    dx: tuple[float, ...]
    kinds: tuple[str, ...]  # boundary kind per side: x_lo, x_hi[, y_lo, y_hi]
    limiter: str = "mc"
    riemann: str = "hllc"
    cfl: float = 0.8
    #: the power k of r in the face areas (:mod:`partmesh.gridref.revolution`): 0 planar, 1 axisymmetric (x is
    #: the distance r from the axis at x = 0, y is z), 2 spherical (1D, x is the distance from the centre)
    radial: int = 0
    #: detonation products and air (:class:`~partmesh.gridref.euler.mixture.Mixture`), or None: an ideal gas
    mixture: object = None

    @property
    def gas(self):
        """What the state conversions take (:mod:`partmesh.gridref.euler.state`): γ, or the mixture."""
        return self.gamma if self.mixture is None else self.mixture

    @property
    def variables(self) -> int:
        """The variables of a cell's state."""
        return self.dim + 2 + scalar_count(self.gas)

    def table(self, n: int) -> RadialTable | None:
        """The radial geometry of a radius of ``n`` cells of this scheme's
        spacing, ghosts included (None when planar)."""
        if not self.radial:
            return None
        return RadialTable(n, self.dx[0], self.radial, N_GHOST, self.kinds[1] == "reflect")


def grid_rings(scheme: Scheme, n: int) -> Rings | None:
    """The :class:`~partmesh.gridref.revolution.Rings` of a whole grid of
    ``n`` cells along the radius (None when planar)."""
    table = scheme.table(n)
    return None if table is None else table.rings(np.arange(-1, n + 1))


def ghosted_primitive(U, states, scheme: Scheme, fill_solids=None):
    """Primitive state with solid ghost cells filled and ``N_GHOST`` boundary
    ghost layers added on every side."""
    W = primitive(U, scheme.gas)
    if fill_solids is not None:
        W = fill_solids(W)
    return with_ghosts(W, scheme.kinds, states)


def slopes_of(Wg, scheme: Scheme):
    """Limited slopes along every direction on the interior plus one ghost
    layer (a list over directions of tuples over variables). Of a mixture,
    the density's slope is the sum of the materials' partial densities'
    limited apart (ρ = ρY + (ρ − ρY)): a cell of one material then keeps
    the other's partial density zero on its faces, which limiting ρ and ρY
    apart does not (Johnsen & Colonius 2006, J. Comput. Phys. 219, 715,
    reconstruct the partial densities)."""
    axes = scheme.axes
    limiter = LIMITERS[scheme.limiter]

    def limited(a, d):
        return cropped(limited_slopes(a, axes[d], limiter), [b for b in axes if b != axes[d]], N_GHOST - 1)

    slopes = [[limited(a, d) for a in Wg] for d in range(scheme.dim)]
    if scheme.mixture is not None:
        k = first_scalar(Wg, scheme.gas)
        for d in range(scheme.dim):
            slopes[d][0] = limited(Wg[0] - Wg[k], d) + slopes[d][k]
    return [tuple(s) for s in slopes]


def half_step(Wg, slopes, dt, scheme: Scheme, allowed=None, rings: Rings | None = None):
    """``(W^{n+1/2}, ok)``: the predictor on the interior plus one ghost
    layer (with the geometric terms of a geometry of revolution, whose
    ``rings`` the cells are), and the
    mask of cells whose face states are physical and
    ``allowed`` (elsewhere ``W^{n+1/2} = W`` and the slopes are ignored: the
    cell is first order)."""
    gas, dx = scheme.gas, scheme.dx
    Wc = tuple(cropped(a, scheme.axes, N_GHOST - 1) for a in Wg)
    changes = [primitive_change(Wc, slopes[d], d, gas) for d in range(scheme.dim)]
    rates = [sum(ch[k] * (1.0 / dx[d]) for d, ch in enumerate(changes)) for k in range(len(Wc))]
    if scheme.radial:  # the geometric terms −g ρ u_r and −g ρc² u_r (cells −1 … n of the interior)
        g = rings.hoop
        rates[0] = rates[0] + g * Wc[0] * Wc[1]
        if scheme.mixture is None:
            rates[-1] = rates[-1] + g * gas * Wc[-1] * Wc[1]
        else:  # and −g q u_r of the partial densities
            for k in density_scalars(Wc, gas):
                rates[k] = rates[k] + g * Wc[k] * Wc[1]
            rates[-1] = rates[-1] + g * stiffness(Wc, gas) * Wc[1]
    Wh = tuple(w - (0.5 * dt) * rate for w, rate in zip(Wc, rates))
    if scheme.mixture is not None:
        Wh = scheme.mixture.bounded(Wh)
    ok = True if allowed is None else allowed
    for d in range(scheme.dim):
        for sign in (-0.5, 0.5):
            ok = ok & (Wh[0] + sign * slopes[d][0] > 0.0) & (Wh[-1] + sign * slopes[d][-1] > 0.0)
    return tuple(jnp.where(ok, a, b) for a, b in zip(Wh, Wc)), ok


def face_flux(Wh, slopes_d, ok, d, scheme: Scheme):
    """Riemann fluxes through the interior faces normal to direction ``d``
    (tuple over conservative variables)."""
    axes = scheme.axes
    others = [b for b in axes if b != axes[d]]
    s = tuple(jnp.where(ok, a, 0.0) for a in slopes_d)
    left = tuple(cropped(_shifted(w + 0.5 * ds, axes[d], True), others) for w, ds in zip(Wh, s))
    right = tuple(cropped(_shifted(w - 0.5 * ds, axes[d], False), others) for w, ds in zip(Wh, s))
    if scheme.mixture is not None:
        left, right = scheme.mixture.bounded(left), scheme.mixture.bounded(right)
    flux = RIEMANN_SOLVERS[scheme.riemann]
    return rotated(flux(rotated(left, d), rotated(right, d), scheme.gas), d)


def _dilated(mask):
    """``mask`` grown by one cell in every direction, diagonals included."""
    for axis in range(mask.ndim):
        mask = mask | jnp.roll(mask, 1, axis) | jnp.roll(mask, -1, axis)
    return mask


#: the vacuum floors, relative to the largest pressure and density in the gas (:func:`vacuum_floored`)
FLOOR = 1e-6


def vacuum_floored(U, gas, fluid=None):
    """``(U, cells, Δρ, ΔE)``: ``U`` with every finite cell of a near-vacuum
    made physical: a non-positive pressure over a positive density raised
    to ``p_f = FLOOR · max p`` by internal energy alone (density and
    momentum kept); a non-positive density set to ``ρ_f = FLOOR · max ρ``
    at rest with pressure ``p_f``. ``cells`` counts them; ``Δρ`` and ``ΔE``
    are the mass and energy per unit volume that changed (0 elsewhere,
    and outside the ``fluid``).

    The last resort after the positivity fallback: in a near-vacuum (the
    attached expansion round the rear of a rod at 0.25 mm, kinetic energy
    10⁴ times the internal; the rear corners of a triangle) the total and
    kinetic energies are updated separately and their difference loses its
    sign to a relative error of 10⁻⁴, however short the step (floors as in
    Athena's or FLASH's). A mixture's empty cell becomes air."""
    W = primitive(U, gas)
    rho, p = W[0], W[-1]
    finite = jnp.all(jnp.stack([jnp.isfinite(a) for a in U]), axis=0)
    live = finite if fluid is None else finite & fluid
    p_f = FLOOR * jnp.max(jnp.where(live & (rho > 0.0) & (p > 0.0), p, 0.0))
    rho_f = FLOOR * jnp.max(jnp.where(live, rho, 0.0))
    empty = live & ~(rho > 0.0)
    low = live & (rho > 0.0) & ~(p > 0.0)
    scalars = parts(U, gas)[2]
    raised = ((p_f - p) / (gas - 1.0) if scalar_count(gas) == 0 else
              (p_f - p) * gas.energy_per_pressure(scalars, jnp))
    E = jnp.where(empty, internal_energy(rho_f, tuple(0.0 * q for q in scalars), p_f, gas),
                  jnp.where(low, U[-1] + raised, U[-1]))
    mass = jnp.where(empty, rho_f, rho)
    momentum = tuple(jnp.where(empty, 0.0, m) for m in U[1:-1])
    return (mass, *momentum, E), jnp.sum(empty | low), jnp.where(live, mass - rho, 0.0), jnp.where(live, E - U[-1], 0.0)


def second_order_allowed(ok, U_new, gas):
    """``ok`` without the cells at or next to a cell whose updated state is
    not physical: the a-posteriori positivity fallback (in the spirit of
    MOOD, Clain, Diot & Loubère 2011) redoes the step with those cells first
    order. ``ok`` covers the interior plus one ghost layer."""
    W = primitive(U_new, gas)
    bad = ~(W[0] > 0.0) | ~(W[-1] > 0.0)
    return ok & ~_dilated(jnp.pad(bad, 1))


def flux_divergence(fluxes, scheme: Scheme, apertures=None, rings: Rings | None = None, counted=None):
    """``(D, side_forces)``: the flux divergence ``Σ_d (α F_{d,i+1/2} −
    α F_{d,i−1/2})/Δx_d`` of every cell from the face fluxes of every
    direction, with the faces' open fractions ``apertures`` (one array per
    direction; all open if None); in a geometry of revolution the radial
    faces weighted by their area and the difference divided by the cell's
    volume (the cells' ``rings``, :mod:`partmesh.gridref.revolution`).

    ``side_forces[i]`` is the normal momentum flux integrated over side
    ``i`` (planar: per metre depth in 2D, per square metre in 1D, the whole
    side in 3D; of revolution: over the whole revolved side): the time-centred force the
    gas exerts on that side; ``counted`` (all 1 if None) weighs the rows (2D)
    or planes (3D) of the first array axis in the forces on the sides along it.
    """
    axes, dx, dim, k = scheme.axes, scheme.dx, scheme.dim, scheme.radial
    divergence = [0.0] * len(fluxes[0])
    forces = []
    for d, F in enumerate(fluxes):
        if apertures is not None:
            F = tuple(f * apertures[d] for f in F)
        n = F[0].shape[axes[d]]
        inv_dx = 1.0 / dx[d]
        if k and d == 0:
            inv_dx = inv_dx / rings.volumes
            F = tuple(f * rings.areas for f in F)
        divergence = [acc + (_shifted(f, axes[d], False) - _shifted(f, axes[d], True)) * inv_dx
                      for acc, f in zip(divergence, F)]
        momentum = F[1 + d] if counted is None or d == dim - 1 else F[1 + d] * counted.reshape((-1,) + (1,) * (dim - 1))
        area = float(np.prod([dx[e] for e in range(dim) if e != d]))  # a face's (1 in 1D; per metre depth in 2D)
        if k:  # the whole turn, and along the radius each face's mean radius (a radial side's is in F already)
            area = REVOLUTION[k] * area * (1.0 if d == 0 else rings.volumes)
            forces += [jnp.sum(jnp.take(momentum, i, axis=axes[d]) * area) for i in (0, n - 1)]
        else:
            forces += [jnp.sum(jnp.take(momentum, i, axis=axes[d])) * area for i in (0, n - 1)]
    return divergence, jnp.stack(forces)


def hoop_source(Wh, scheme: Scheme, rings: Rings):
    """The pressure's source ``p g`` of the radial momentum in a geometry of
    revolution (``Wh`` the half-step state on the interior plus one ghost
    layer, the cells' ``rings``), which D's radial momentum carries with a
    minus sign (:mod:`partmesh.gridref.revolution`)."""
    return cropped(Wh[-1], scheme.axes) * rings.hoop[(slice(1, -1),) * rings.hoop.ndim]


def advanced(U, divergence, dt, gas):
    """``U − Δt D``; a mixture's volume fraction α, advected, ``α − Δt (D_α − α D_u)``
    with ``D_u`` the divergence of the faces' volume flux (the last of ``divergence``,
    :func:`partmesh.gridref.euler.riemann.hllc`), clipped to [0, 1] and kept admissible
    (:meth:`partmesh.gridref.euler.mixture.Mixture.admissible`)."""
    new = [u - dt * div for u, div in zip(U, divergence)]
    if not scalar_count(gas):
        return tuple(new)
    new[-2] = jnp.clip(U[-2] - dt * (divergence[-3] - U[-2] * divergence[-1]), 0.0, 1.0)
    return gas.admissible(tuple(new))


def flux_update(U, fluxes, dt, scheme: Scheme, Wh=None, immersed=None, rings: Rings | None = None, counted=None):
    """``(U^{n+1}, side_forces)`` from the face fluxes of every direction
    (:func:`flux_divergence`; of revolution, on cells of ``rings``); with
    an ``immersed`` boundary, the cut-cell
    update with its walls' pressure from the half-step state ``Wh`` (the
    interior plus one ghost layer) and flux redistribution
    (:mod:`partmesh.gridref.euler.immersed`); ``counted`` weighs the rows
    in the side forces (:func:`flux_divergence`)."""
    if immersed is None:
        divergence, forces = flux_divergence(fluxes, scheme, rings=rings, counted=counted)
        if scheme.radial:
            divergence[1] = divergence[1] - hoop_source(Wh, scheme, rings)
        return advanced(U, divergence, dt, scheme.gas), forces
    divergence, forces = cut_cell_divergence(fluxes, Wh, scheme, immersed, rings)
    return immersed.advanced(U, divergence, dt), forces


def cut_cell_divergence(fluxes, Wh, scheme: Scheme, immersed, rings: Rings | None = None):
    """``(D, side_forces)``: the right-hand side of the cut-cell update,
    the faces' fluxes through their open fractions plus the walls'
    pressure from the half-step state ``Wh`` (the interior plus one ghost
    layer), per full cell volume; of revolution, less the hoop source of
    the cell's open part (which the wall vector balances for a gas at rest)."""
    divergence, forces = flux_divergence(fluxes, scheme, immersed.apertures, rings)
    W = tuple(cropped(a, scheme.axes) for a in Wh)
    walls = immersed.wall_divergence(W, scheme.gamma, scheme.riemann)
    divergence = [d + w for d, w in zip(divergence, walls)]
    if scheme.radial:  # the hoop source of the open part of each cell
        divergence[1] = divergence[1] - immersed.volume * hoop_source(Wh, scheme, rings)
    return divergence, forces


#: the cells of a strip (:func:`strip_rows`): a strip's arrays stay in the processor's caches between kernels
#: (0: every grid stepped whole)
STRIP_CELLS = 32768


def strip_rows(shape) -> int | None:
    """The rows (2D, along y) or planes (3D, along z) of each strip of a
    grid of ``shape`` (``(y, x)`` or ``(z, y, x)``) that
    :func:`strip_attempt` steps in turn: as many as :data:`STRIP_CELLS`
    allows, at least four, and at least two strips; None for a 1D grid or one too
    small to be split, off the CPU, where a loop over strips would
    serialise what the device runs in parallel (the grid is stepped whole),
    and where devices share the grid (:mod:`partmesh.gridref.sharding`)."""
    if (len(shape) < 2 or shape[0] < 8 or not STRIP_CELLS or jax.default_backend() != "cpu"
            or jax.device_count() > 1):
        return None
    return max(4, min(shape[0] // 2, STRIP_CELLS // int(np.prod(shape[1:]))))


class Paired(NamedTuple):
    """A state stepped in strips (:func:`strip_attempt`), kept as two grids:
    each variable's array holds the state at half ``current`` of its first
    axis (of length 2) and the state before it at the other half, which the
    next step overwrites. A step so reads one half and writes the other in
    place: no pass over the grid clears, allocates or copies a state (as a
    new state beside the old would: cleared before the strips write it,
    then copied into the stepping loop's state)."""

    halves: tuple
    current: jax.Array

    @classmethod
    def of(cls, U) -> "Paired":
        """The pair holding ``U`` (in both halves)."""
        return cls(tuple(jnp.stack([u, u]) for u in U), jnp.zeros((), jnp.int32))

    def state(self) -> tuple:
        """The current state ``U``."""
        return tuple(jax.lax.dynamic_index_in_dim(a, self.current, keepdims=False) for a in self.halves)

    def replaced(self, U) -> "Paired":
        """The pair whose current state is ``U`` in place of its own."""
        return Paired(tuple(_put_rows(a, u, self.current, 0) for a, u in zip(self.halves, U)), self.current)


def _rows(a, half, start, n: int):
    """``n`` rows of half ``half`` of a pair's array ``a`` (:class:`Paired`) from row ``start``."""
    return jax.lax.dynamic_slice(a, _corner(a, half, start), (1, n) + a.shape[2:])[0]


def _put_rows(a, rows, half, start):
    """``a`` (a pair's array) with ``rows`` written into half ``half`` from row ``start``."""
    return jax.lax.dynamic_update_slice(a, rows[None], _corner(a, half, start))


def _corner(a, half, start) -> tuple:
    """The index of row ``start`` of half ``half`` of a pair's array ``a``, in one integer type."""
    return tuple(jnp.asarray(i, jnp.int32) for i in (half, start) + (0,) * (a.ndim - 2))


def strip_attempt(pair: Paired, allowed, dt, scheme: Scheme, rows: int, gate, states, rings: Rings | None = None,
                  after: Callable | None = None):
    """``(pair', ok, side_forces, dt_next)`` of a 2D or 3D grid without bodies,
    stepped in strips of ``rows`` rows of its first array axis (y in 2D, z in 3D; ghost cells, slopes, predictor,
    fluxes, update and CFL step of one strip, then the next): the same
    arithmetic cell by cell as the whole grid's pipeline, but each strip's
    intermediate arrays stay in the processor's caches, where the whole
    grid's spill to memory from about 10⁵ cells on (a 2048² step at a third
    of a 256² step's rate per cell). ``allowed``: the cells second order,
    on the interior plus one ghost layer; ``states``: the inflow states.
    The state is ``pair``'s current half (:class:`Paired`); the strips
    write ``U^{n+1}`` over its other half, which ``pair'`` makes current.
    Where ``rows`` does not divide the grid, the
    last strip ends at the last row and overlaps the one before: its
    overlapping rows come out the same and count once in the side forces.
    ``after(U_s, start)``, where given, changes each updated strip (beginning at row ``start``) before
    its CFL step is taken (the programmed burn). Beside a charge, a strip whose cells and ghost rows hold no
    explosive (its three scalars zero, as they stay) is stepped with the air's ideal-gas kernels."""
    ny, g = pair.halves[0].shape[1], N_GHOST
    now = pair.current
    last = ny - rows
    across = tuple(range(scheme.dim - 1))  # the directions along a strip (x; x and y in 3D)
    crowding = None if rings is None else rings.crowding

    def stepper(scheme, chosen, states, after):
        """The step of one strip of the variables ``chosen`` (indices into the pair's halves) as a state of
        ``scheme``: ``(start, counted, allowed_s, halves) -> (U_s, ok_s, forces_s, dt_s)``, reading the
        current half of ``halves`` (the strips' loop carries the pair it writes)."""
        gas = scheme.gas
        # the strip axis's ghost rows: those of the first and last rows alone, ghosted as the whole grid is
        edges = tuple(jnp.concatenate([_rows(pair.halves[i], now, 0, g), _rows(pair.halves[i], now, ny - g, g)])
                      for i in chosen)
        edges = staged(lambda E: ghosted_primitive(E, states, scheme), gate)(edges)

        def window(U, start):
            """The strip's primitive state with its ghost cells: its neighbours' rows or the end sides' ghosts."""
            above = [_rows(u, now, jnp.maximum(start - g, 0), g) for u in U]
            below = [_rows(u, now, jnp.minimum(start + rows, ny - g), g) for u in U]
            inner = [_rows(u, now, start, rows) for u in U]
            W = primitive(tuple(jnp.concatenate(parts) for parts in zip(above, inner, below)), gas)
            W = with_ghosts(W, scheme.kinds, states, directions=across)
            return tuple(jnp.concatenate([jnp.where(start == 0, e[:g], w[:g]), w[g:-g],
                                          jnp.where(start == last, e[-g:], w[-g:])]) for w, e in zip(W, edges))

        def step(start, counted, allowed_s, halves):
            U = tuple(halves[i] for i in chosen)
            Wg = staged(window, gate)(U, start)
            slopes = staged(lambda Wg: slopes_of(Wg, scheme), gate)(Wg)
            Wh, ok_s = staged(lambda Wg, s, allowed: half_step(Wg, s, dt, scheme, allowed, rings), gate)(
                Wg, slopes, allowed_s)
            fluxes = [staged(lambda Wh, s, ok, d=d: face_flux(Wh, s, ok, d, scheme), gate)(Wh, slopes[d], ok_s)
                      for d in range(scheme.dim)]

            def updated(F, Wh, counted, U):
                U_s = tuple(_rows(u, now, start, rows) for u in U)
                U_s, forces = flux_update(U_s, F, dt, scheme, Wh, rings=rings, counted=counted)
                if after is not None:
                    U_s = after(U_s, start)
                return U_s, forces, stable_dt(U_s, gas, scheme.dx, scheme.cfl, None, crowding)

            U_s, forces_s, dt_s = staged(updated, gate)(fluxes, Wh, counted, U)
            return U_s, ok_s, forces_s, dt_s
        return step

    every = tuple(range(len(pair.halves)))
    step = stepper(scheme, every, states, after)
    if scheme.mixture is not None:
        # a strip whose cells and ghost rows hold no explosive is stepped as the air it is, at the gas's cost
        n = first_scalar(every, scheme.gas)
        scalars = every[n:-1]
        euler = [*every[:n], every[-1]]  # (ρ, momentum, E)
        air = stepper(dataclasses.replace(scheme, mixture=None), euler, states[:, euler], None)

        def air_step(start, counted, allowed_s, halves):
            U_s, ok_s, forces_s, dt_s = air(start, counted, allowed_s, halves)
            zero = jnp.zeros_like(U_s[0])
            return (*U_s[:-1], *(zero,) * scheme.mixture.scalars, U_s[-1]), ok_s, forces_s, dt_s

        mixture_step = step

        def step(start, counted, allowed_s, halves):
            lo = jnp.clip(start - g, 0, ny - rows - 2 * g)
            charged = jnp.any(jnp.stack([jnp.any(_rows(halves[i], now, lo, rows + 2 * g) != 0.0) for i in scalars]))
            return jax.lax.cond(charged, mixture_step, air_step, start, counted, allowed_s, halves)

    later = 1 - now

    def strip(k, carry):
        halves, ok, forces, dt_next = carry
        start = jnp.minimum(k * rows, last)
        counted = (start + jnp.arange(rows) >= k * rows).astype(halves[0].dtype)
        allowed_s = jax.lax.dynamic_slice_in_dim(allowed, start, rows + 2)
        U_s, ok_s, forces_s, dt_s = step(start, counted, allowed_s, halves)
        # the sides along the strips through every strip; the end sides through the first and last strips' outer faces
        sides = jnp.array([True, True] * len(across) + [start == 0, start == last], dtype=forces_s.dtype)
        return (tuple(_put_rows(a, b, later, start) for a, b in zip(halves, U_s)),
                jax.lax.dynamic_update_slice_in_dim(ok, ok_s, start, 0), forces + sides * forces_s,
                jnp.minimum(dt_next, dt_s))

    start = (pair.halves, jnp.zeros(allowed.shape, bool), jnp.zeros(2 * scheme.dim), jnp.array(jnp.inf))
    halves, ok, forces, dt_next = jax.lax.fori_loop(0, -(-ny // rows), strip, start)
    return Paired(halves, later), ok, forces, dt_next


def with_fallbacks(attempt: Callable, allowed_after: Callable, floored: Callable, allowed, retries: int, start):
    """``(out, added)``: the step ``attempt(allowed, previous) -> (out, ok)``
    (``out = (U_new, dt_next, ...)``, ``dt_next`` NaN where ``U_new`` is not
    physical; ``previous`` the last attempt's ``out``, whose arrays it may
    overwrite) taken with the cells ``allowed`` second order, then redone up
    to ``retries`` times with ``allowed_after(ok, U_new)`` (fewer cells
    second order: the a-posteriori positivity fallback); if it is still not
    physical, ``floored(U_new) -> (U, dt_next, cells, mass, energy)`` (the
    vacuum floors, :func:`vacuum_floored`) as the last resort. ``added``
    counts the cells the floors changed and the mass and energy they added
    (zeros when none did).

    The first attempt is the loop's first pass, so the program holds the
    step once: ``start`` is an ``out`` of the shapes ``attempt`` returns (any
    values: none is read)."""
    def tried(carry):
        out, ok, k = carry
        chosen = jax.lax.cond(k == 0, lambda ok, U: allowed, allowed_after, ok, out[0])
        out, ok = attempt(chosen, out)
        return out, ok, k + 1

    def again(carry):
        out, _, k = carry
        return (k == 0) | (jnp.isnan(out[1]) & (k <= retries))

    out, _, _ = jax.lax.while_loop(again, tried, (start, allowed, 0))

    def with_floors(_, carry):
        out, _ = carry
        U_new, dt_next, cells, mass, energy = floored(out[0])
        return (U_new, dt_next, *out[2:]), jnp.stack([cells.astype(float), mass, energy])

    # (a loop of one pass or none, not a conditional: the branch that passes the state through unchanged copied
    # every array of it, each step)
    return jax.lax.fori_loop(0, jnp.where(jnp.isnan(out[1]), 1, 0), with_floors, (out, jnp.zeros(3)))


class Stepper:
    """The MUSCL–Hancock step of one run, and stretches of it on the device.

    :meth:`step` is the pure step ``(U, floors), t, dt -> ((U', floors'),
    dt_next, probes, side_forces)``: the inflow states of time ``t``
    (``inflow(t)``, traced), the step, the a-posteriori positivity fallback
    (the step redone with more cells first order, up to :attr:`RETRIES`
    times) and the vacuum floors (:func:`vacuum_floored`) as the last
    resort; ``dt_next`` is the CFL step of the new state, NaN if it is not
    physical even then. ``floors`` counts the cells the floors changed and
    the mass and energy they added [kg and J, per metre depth in a planar 2D
    run, over the whole body in a geometry of revolution]. With a charge
    (``scheme.mixture``), the cells' ``lighting`` times drive its programmed
    burn (:func:`partmesh.gridref.euler.mixture.burnt`) at the end of every step.
    :attr:`stretch` (:func:`partmesh.gridref.device_loop.device_loop`) runs it in one
    compiled loop; ``stepper(U, dt, t)`` is one step for a caller that
    steps on the host (the hybrid method).

    The kernels are materialised in between (see the module docstring and
    :mod:`partmesh.gridref.staging`).
    """

    #: how often a step is redone with more cells first order before the
    #: state is declared unphysical
    RETRIES = 2

    def __init__(self, scheme: Scheme, immersed=None, solid_state=None, probe_sampler: Callable | None = None,
                 n_probes: int = 0, inflow: Callable | None = None, n_records: int = 1024, lighting=None):
        self.scheme = scheme
        fluid = None if immersed is None else jnp.asarray(immersed.fluid)
        open_fraction = 1.0 if immersed is None else immersed.volume

        def cfl_dt(U):
            rings = grid_rings(scheme, U[0].shape[-1])
            return stable_dt(U, scheme.gas, scheme.dx, scheme.cfl, fluid, None if rings is None else rings.crowding)
        fill_solids = None if immersed is None else immersed.fill
        no_inflow = jnp.zeros((2 * scheme.dim, scheme.variables))
        inflow = inflow or (lambda t: no_inflow)

        def burn(U, t, start=0):
            """``U`` at time ``t`` with its charge burnt as far as the front has come (``start``: its first row)."""
            if lighting is None:
                return U
            light = jnp.asarray(lighting)
            if light.shape[0] != U[0].shape[0]:
                light = jax.lax.dynamic_slice_in_dim(light, start, U[0].shape[0])
            return burnt(U, light, t, scheme.dx[0], scheme.mixture.burn_speed)

        def checked(U_new, forces, t_new):
            U_new = burn(U_new, t_new)
            probes = probe_sampler(U_new) if probe_sampler is not None else jnp.zeros(0)
            return U_new, cfl_dt(U_new), forces, probes

        def update(U, F, Wh, t, dt, gate):
            rings = grid_rings(scheme, U[0].shape[-1])
            if immersed is None:
                return staged(lambda U, F, Wh, t, dt: checked(*flux_update(U, F, dt, scheme, Wh, rings=rings), t + dt),
                              gate)(U, F, Wh, t, dt)
            # the cut-cell update in three stages: its right-hand side, the redistribution (which reads
            # the right-hand side of every neighbour), the reset of the solid cells with the checks
            D, forces = staged(lambda F, Wh: cut_cell_divergence(F, Wh, scheme, immersed, rings), gate)(F, Wh)
            U_new = staged(lambda U, D, dt: immersed.advanced(U, D, dt), gate)(U, D, dt)
            return staged(lambda U_new, forces, t_new: checked(immersed.reset(U_new, solid_state), forces, t_new),
                          gate)(U_new, forces, t + dt)

        def floored(U):
            U, cells, mass, energy = vacuum_floored(U, scheme.gas, fluid)
            open_volume = np.prod(scheme.dx) * revolved(U[0].shape, scheme.dx[0], scheme.radial) * open_fraction
            return U, cfl_dt(U), cells, jnp.sum(mass * open_volume), jnp.sum(energy * open_volume)

        def step(state, t, dt):
            held, floors = state
            in_strips = isinstance(held, Paired)  # (see paired below)
            shape = held.halves[0].shape[1:] if in_strips else held[0].shape
            gate = jnp.isfinite(dt)
            rings = grid_rings(scheme, shape[-1])
            if not in_strips:
                Wg = staged(lambda U, states: ghosted_primitive(U, states, scheme, fill_solids), gate)(held, inflow(t))
                slopes = staged(lambda Wg: slopes_of(Wg, scheme), gate)(Wg)

            def attempt(allowed, previous):
                if in_strips:  # (stepped from the step's state: a redone step's pair holds it at the same half)
                    pair, ok, forces, dt_next = strip_attempt(Paired(previous[0].halves, held.current), allowed, dt,
                                                              scheme, strip_rows(shape), gate, inflow(t), rings,
                                                              lambda U, start: burn(U, t + dt, start))
                    probes = probe_sampler(pair.state()) if probe_sampler is not None else jnp.zeros(0)
                    return (pair, dt_next, forces, probes), ok
                Wh, ok = staged(lambda Wg, s, allowed: half_step(Wg, s, dt, scheme, allowed, rings), gate)(
                    Wg, slopes, allowed)
                fluxes = [staged(lambda Wh, s, ok, d=d: face_flux(Wh, s, ok, d, scheme), gate)(Wh, slopes[d], ok)
                          for d in range(scheme.dim)]
                return update(held, fluxes, Wh, t, dt, gate), ok

            def allowed_after(ok, new):
                return staged(lambda ok, new: second_order_allowed(ok, new.state() if in_strips else new, scheme.gas),
                              gate)(ok, new)

            def floored_held(new):
                if not in_strips:
                    return floored(new)
                U, *rest = floored(new.state())
                return (new.replaced(U), *rest)

            first = jnp.ones(tuple(n + 2 for n in shape), bool)
            start = (held if in_strips else tuple(jnp.zeros_like(u) for u in held), jnp.zeros(()),
                     jnp.zeros(2 * scheme.dim), jnp.zeros(n_probes if probe_sampler else 0))
            (new, dt_next, forces, probes), added = with_fallbacks(attempt, allowed_after, staged(floored_held, gate),
                                                                   first, self.RETRIES, start)
            return (new, floors + added), dt_next, probes, forces

        def paired(state):
            """The loop's state of a run's ``(U, floors)``: a grid stepped in strips holds ``U`` as a
            :class:`Paired`, whose halves the steps write in turn."""
            U, floors = state
            if immersed is not None or strip_rows(U[0].shape) is None:
                return state
            return Paired.of(U), floors

        def unpaired(state):
            """The run's ``(U, floors)`` of a loop's state (:func:`paired`)."""
            held, floors = state
            return (held.state(), floors) if isinstance(held, Paired) else state

        def one_step(state, t, dt):
            new, dt_next, probes, forces = step(paired(state), t, dt)
            return unpaired(new), dt_next, probes, forces

        self.step = step
        #: one step, compiled when first called
        self.one_step = jax.jit(one_step)
        self.stretch = device_loop(step, n_probes, 2 * scheme.dim, n_records, enter=paired, leave=unpaired)
        self.initial_dt = jax.jit(cfl_dt)

    @staticmethod
    def start(U):
        """The loop state of ``U``: the state and its floor counts (none yet)."""
        return U, jnp.zeros(3)

    def __call__(self, U, dt, t):
        """``(U after one step of dt from time t, its CFL step as a float (NaN: not physical), side forces,
        probes)``."""
        (U_new, _), dt_next, probes, forces = self.one_step(self.start(U), t, dt)
        return U_new, float(dt_next), forces, probes

    def compile(self, U) -> None:
        """Compile the stretch for these shapes (and the first CFL step)."""
        jax.block_until_ready(self.initial_dt(U))
        self.stretch.compile(self.start(U))
