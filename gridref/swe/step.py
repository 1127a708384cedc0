"""One step of the shallow-water model: MUSCL reconstruction, hydrostatic
reconstruction at the faces, HLLC fluxes, SSP Runge–Kutta 2 in time.

Equations (Toro 2001; Audusse, Bouchut, Bristeau, Klein & Perthame 2004,
SIAM J. Sci. Comput. 25, 2050), with depth ``h``, velocity ``(u, v)``, bed
elevation ``z`` and ``η = h + z`` the free surface::

    h_t + (h u)_x + (h v)_y = 0
    (h u)_t + (h u² + g h²/2)_x + (h u v)_y = −g h z_x
    (h v)_t + (h u v)_x + (h v² + g h²/2)_y = −g h z_y

and in 1D-radial geometry (r = x, axisymmetric) ``(r h)_t + (r h u)_r = 0``,
``(r h u)_t + (r (h u² + g h²/2))_r = g h²/2 − r g h z_r``.

Per direction: limited slopes of ``h``, ``η`` and the velocities give face
states (``z = η − h`` at a face, so a lake at rest reconstructs a flat
surface, and the face depths lie between the neighbours' depths, never
negative). The hydrostatic reconstruction (Audusse et al. 2004) puts both
sides on the face bed ``z* = max(z⁻, z⁺)`` with depths
``h*± = max(0, h± + z± − z*)``; the HLLC flux of those states
(:mod:`gridref.swe.fluxes`) is corrected by ``g (h±² − h*±²)/2`` in the
normal momentum on each side, and the cell gets the centred bed source
``−g (h⁺_{i−½} + h⁻_{i+½})/2 · (z⁻_{i+½} − z⁺_{i−½})/Δx``: a lake at rest
over any bed stays at rest to round-off, and the depth stays ≥ 0 for
Courant numbers ≤ 1/4 (half the first-order bound 1/2 because of the
reconstruction; Audusse et al. 2004 §4). In radial geometry the face fluxes
are weighted by the face radius, the cell by its centre radius, and the
hoop term ``g h²/(2r)`` is taken as ``g (h⁻²_{i+½} + h⁺²_{i−½})/(4 r_i)``,
which balances the pressure fluxes of a lake at rest exactly.

The ghosted state, each direction's face fluxes and cell terms, and the
stage updates are separate jitted kernels whose outputs are materialised in
between (:class:`gridref.swe.solve.Stepper`), and within the flux kernel the
face values and the fluxes are materialised too
(``jax.lax.optimization_barrier``): fused into their consumers, XLA:CPU
recomputes them for every use (a step on 512² cells: 196 ms with each
direction's fluxes and terms in one kernel, 67 ms apart, of which the flux
kernels take 8.5 ms per direction and stage).

Velocities are recovered from the momenta with Kurganov & Petrova's (2007)
desingularisation ``u = 2 h (h u)/(h² + max(h², ε²))`` (ε = ``DRY`` m), so a
nearly dry cell cannot produce a large velocity.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from gridref.euler.boundaries import N_GHOST, axis_of, ghost_layer
from gridref.euler.reconstruct import LIMITERS, limited_slopes
from gridref.grid import cropped
from gridref.swe.fluxes import hllc

#: depth [m] below which a cell counts as dry for its velocity (desingularisation ε)
DRY = 1e-6


@dataclass(frozen=True)
class Scheme:
    """Settings of one shallow-water run."""

    g: float
    dx: tuple[float, ...]
    kinds: tuple[str, ...]  # boundary kind per side, x_lo, x_hi[, y_lo, y_hi] (cases.scene.WaterScene.boundary_kinds)
    radial: bool = False
    limiter: str = "mc"
    cfl: float = 0.25

    @property
    def dim(self) -> int:
        return len(self.dx)


def velocities(U):
    """Velocities ``(u[, v])`` from ``(h, h u[, h v])``, desingularised."""
    h = U[0]
    inverse = 2.0 * h / (h * h + jnp.maximum(h * h, DRY * DRY))
    return tuple(m * inverse for m in U[1:])


def _absorbing(W, axis, side, g):
    """Ghost cells beyond an absorbing side: the outgoing Riemann invariant
    ``u_n + 2c`` from the edge cell, the incoming one ``−2 sqrt(g h₀)`` of
    still water (``h₀ = max(0, −z)``, the surface at rest at η = 0), the
    tangential velocity and the bed from the edge cell (a linear
    characteristic condition: long waves leave without reflection)."""
    h, *vel, z = W
    n = h.shape[axis]
    take = (lambda a: jax.lax.slice_in_dim(a, 0, 1, axis=axis)) if side == "lo" else \
        (lambda a: jax.lax.slice_in_dim(a, n - 1, n, axis=axis))
    sign = -1.0 if side == "lo" else 1.0
    d = len(vel) - 1 - axis  # the direction normal to this side
    he, ze = take(h), take(z)
    un = sign * take(vel[d])
    c_out, c_still = jnp.sqrt(g * he), jnp.sqrt(g * jnp.maximum(-ze, 0.0))
    un_b = 0.5 * (un + 2.0 * c_out - 2.0 * c_still)
    c_b = 0.25 * (un + 2.0 * c_out + 2.0 * c_still)
    edge = [c_b * c_b / g] + [take(v) for v in vel] + [ze]
    edge[1 + d] = sign * un_b
    return tuple(jnp.repeat(a, N_GHOST, axis=axis) for a in edge)


def with_ghosts(W, scheme: Scheme):
    """``(h, u[, v], z)`` padded with ``N_GHOST`` ghost cells on every side."""
    dim = scheme.dim
    for d in range(dim):
        axis = axis_of(dim, d)
        sides = []
        for side, kind in zip(("lo", "hi"), scheme.kinds[2 * d: 2 * d + 2]):
            if kind == "absorbing":
                sides.append(_absorbing(W, axis, side, scheme.g))
            else:
                rule = "reflect" if kind == "axis" else kind
                sides.append(tuple(ghost_layer(a, axis, side, rule, flip=(k == 1 + d)) for k, a in enumerate(W)))
        W = tuple(jnp.concatenate([lo, a, hi], axis=axis) for lo, hi, a in zip(*sides, W))
    return W


def _across(upper, lower, axis):
    """Per cell, the face quantity ``upper`` at its upper face minus
    ``lower`` at its lower face (both given on all faces)."""
    return _trimmed(upper, axis, 1, 0) - _trimmed(lower, axis, 0, 1)


def _trimmed(a, axis, lo, hi):
    """``a`` without ``lo`` entries at the start and ``hi`` at the end of ``axis``."""
    return jax.lax.slice_in_dim(a, lo, a.shape[axis] - hi, axis=axis)


def ghosted(U, z, scheme: Scheme):
    """``(h, u[, v], z)`` of the state ``U`` over the bed ``z``, with ghost cells."""
    return with_ghosts((U[0], *velocities(U), z), scheme)


def _face_values(Wg, d: int, scheme: Scheme):
    """``(plus, minus)``: the limited reconstructions of ``(h, η, u[, v])``
    at the upper and lower face of cells 1 .. n+2 of the ghosted rows along
    direction ``d`` (one ghost layer each side), and the cropped axis."""
    dim = scheme.dim
    axes = [axis_of(dim, k) for k in range(dim)]
    axis = axes[d]
    h, *vel, zg = (cropped(a, [a_ for a_ in axes if a_ != axis], N_GHOST) for a in Wg)
    limiter = LIMITERS[scheme.limiter]
    cells = [_trimmed(a, axis, 1, 1) for a in (h, h + zg, *vel)]
    slopes = [limited_slopes(a, axis, limiter) for a in (h, h + zg, *vel)]
    plus = [c + 0.5 * s for c, s in zip(cells, slopes)]   # values at each cell's upper face
    minus = [c - 0.5 * s for c, s in zip(cells, slopes)]  # values at each cell's lower face
    return plus, minus, axis


def face_fluxes(Wg, d: int, scheme: Scheme):
    """``(mass, normal momentum from the left, from the right, tangential
    momentum)`` through the faces normal to direction ``d``: the HLLC flux
    of the hydrostatically reconstructed states, its normal momentum
    corrected by g (h±² − h*±²)/2 on each side (module docstring)."""
    g, dim = scheme.g, scheme.dim
    plus, minus, axis = _face_values(Wg, d, scheme)
    plus, minus = jax.lax.optimization_barrier((plus, minus))
    # face j lies between cells j and j + 1 of these rows: left state from plus, right from minus
    (hL, etaL, *velL), (hR, etaR, *velR) = ([_trimmed(a, axis, 0, 1) for a in plus],
                                            [_trimmed(a, axis, 1, 0) for a in minus])
    zL, zR = etaL - hL, etaR - hR
    z_face = jnp.maximum(zL, zR)
    hL_star, hR_star = jnp.maximum(0.0, hL + zL - z_face), jnp.maximum(0.0, hR + zR - z_face)
    tangential_L = velL[1 - d] if dim == 2 else jnp.zeros_like(hL)
    tangential_R = velR[1 - d] if dim == 2 else jnp.zeros_like(hR)
    mass, mom_n, mom_t = jax.lax.optimization_barrier(
        hllc(hL_star, velL[d], tangential_L, hR_star, velR[d], tangential_R, g))
    from_left = mom_n + 0.5 * g * (hL * hL - hL_star * hL_star)    # the flux cell j sees at its upper face
    from_right = mom_n + 0.5 * g * (hR * hR - hR_star * hR_star)   # the flux cell j + 1 sees at its lower face
    return mass, from_left, from_right, mom_t


def direction_terms(Wg, fluxes, d: int, scheme: Scheme, radius=None):
    """The part of ``dU/dt`` (one array per component of ``U``) that the faces
    normal to direction ``d`` give, from their :func:`face_fluxes`: flux
    differences, the bed source and, radially, the hoop term; ``radius``:
    the cell-centre and face radii ``(r_c, r_f)`` of a radial run."""
    g, dim = scheme.g, scheme.dim
    mass, from_left, from_right, mom_t = fluxes
    plus, minus, axis = _face_values(Wg, d, scheme)
    # each interior cell i: its upper face is face i + 1, its lower face face i; its own face values
    h_up, h_lo = _trimmed(plus[0], axis, 1, 1), _trimmed(minus[0], axis, 1, 1)
    z_up, z_lo = _trimmed(plus[1] - plus[0], axis, 1, 1), _trimmed(minus[1] - minus[0], axis, 1, 1)
    inv_dx = 1.0 / scheme.dx[d]
    source = -0.5 * g * (h_lo + h_up) * (z_up - z_lo) * inv_dx
    face, cell = radius[::-1] if radius is not None else (1.0, 1.0)  # radial: face and centre radii
    out = [jnp.zeros_like(h_up) for _ in range(dim + 1)]
    out[0] = -_across(face * mass, face * mass, axis) * inv_dx / cell
    out[1 + d] = -_across(face * from_left, face * from_right, axis) * inv_dx / cell + source
    if radius is not None:
        out[1 + d] = out[1 + d] + 0.25 * g * (h_up * h_up + h_lo * h_lo) / cell  # the hoop term
    if dim == 2:
        out[2 - d] = -_across(mom_t, mom_t, axis) * inv_dx
    return tuple(out)


def summed(parts):
    """The sum over directions of :func:`direction_terms`, component by component."""
    return tuple(sum(p[k] for p in parts) for k in range(len(parts[0])))


def rates(U, z, scheme: Scheme, radius=None):
    """``dU/dt`` of the semi-discrete scheme (module docstring) for the state
    ``U = (h, h u[, h v])`` over the bed ``z``."""
    Wg = ghosted(U, z, scheme)
    return summed([direction_terms(Wg, face_fluxes(Wg, d, scheme), d, scheme, radius) for d in range(scheme.dim)])


def stable_dt(U, scheme: Scheme):
    """``Δt = C / max Σ_d (|u_d| + sqrt(g h))/Δx_d`` over the wet cells; NaN
    if a depth is negative or a value not finite (the caller reports where)."""
    h = U[0]
    c = jnp.sqrt(scheme.g * jnp.maximum(h, 0.0))
    rate = sum((jnp.abs(v) + c) / dx for v, dx in zip(velocities(U), scheme.dx))
    bad = (h < 0.0) | ~jnp.isfinite(rate) | ~jnp.all(jnp.stack([jnp.isfinite(a) for a in U]), axis=0)
    return jnp.where(jnp.any(bad), jnp.nan, scheme.cfl / jnp.maximum(jnp.max(rate), 1e-300))


def heun_first(U, L, dt):
    """The first stage of Heun's method: ``U¹ = U + Δt L``."""
    return tuple(u + dt * r for u, r in zip(U, L))


def heun_second(U, U1, L1, dt):
    """The second stage of Heun's method: ``Uⁿ⁺¹ = (U + U¹ + Δt L(U¹))/2``."""
    return tuple(0.5 * (u + u1 + dt * r) for u, u1, r in zip(U, U1, L1))


def ssp_rk2(U, z, dt, scheme: Scheme, radius=None):
    """Heun's method, the second-order strong-stability-preserving Runge–Kutta
    scheme (Shu & Osher 1988), in one function (the solver runs the same
    stages as a pipeline, :class:`gridref.swe.solve.Stepper`)."""
    U1 = heun_first(U, rates(U, z, scheme, radius), dt)
    return heun_second(U, U1, rates(U1, z, scheme, radius), dt)


def radii(x_centres, dx):
    """Cell-centre and face radii ``(r_c, r_f)`` of a radial grid."""
    r_c = np.asarray(x_centres, float)
    r_f = np.concatenate([r_c - 0.5 * dx, r_c[-1:] + 0.5 * dx])
    return jnp.asarray(r_c), jnp.asarray(r_f)
