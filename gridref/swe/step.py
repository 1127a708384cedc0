"""One step of the shallow-water model: MUSCL–Hancock with hydrostatic
reconstruction at the faces and HLLC fluxes.

Equations (Toro 2001; Audusse, Bouchut, Bristeau, Klein & Perthame 2004,
SIAM J. Sci. Comput. 25, 2050), with depth ``h``, velocity ``(u, v)``, bed
elevation ``z`` and ``η = h + z`` the free surface::

    h_t + (h u)_x + (h v)_y = 0
    (h u)_t + (h u² + g h²/2)_x + (h u v)_y = −g h z_x
    (h v)_t + (h u v)_x + (h v² + g h²/2)_y = −g h z_y

and in 1D-radial geometry (r = x, axisymmetric) ``(r h)_t + (r h u)_r = 0``,
``(r h u)_t + (r (h u² + g h²/2))_r = g h²/2 − r g h z_r``.

The step is the unsplit MUSCL–Hancock scheme (van Leer 1984; Toro 2009
§14.4), one flux evaluation per face and step:

1. *Slopes*: limited slopes ``Δ`` of ``h``, ``η`` and the velocities along
   each direction (``Δz = Δη − Δh``, so a lake at rest reconstructs a flat
   surface).
2. *Predictor*: each cell's centre values advance half a step with the
   primitive equations ``h_t = −∇·(h u)``, ``u_t = −(u·∇) u − g ∇η``
   (radially ``h_t`` also has ``−h u/r``) evaluated from the slopes:
   ``h̃ = h − Δt/2 Σ_d (u_d Δ_d h + h Δ_d u_d)/Δx_d``,
   ``ũ_k = u_k − Δt/2 (Σ_d u_d Δ_d u_k/Δx_d + g Δ_k η/Δx_k)``. A lake at
   rest has no increments. The bed is not predicted: the face beds are
   ``z ± Δz/2`` and the face depths ``max(0, h̃ ± Δh/2)``.
3. *Faces*: the hydrostatic reconstruction (Audusse et al. 2004) puts both
   face states on the face bed ``z* = max(z⁻, z⁺)`` with depths
   ``h*± = max(0, h± + z± − z*)``; the HLLC flux of those states
   (:mod:`partmesh.gridref.swe.fluxes`) is corrected by ``g (h±² − h*±²)/2`` in the
   normal momentum on each side.
4. *Update*: ``Uⁿ⁺¹ = Uⁿ − Δt Σ_d (flux differences)/Δx_d + Δt S`` with
   the centred bed source ``−g (h⁺_{i−½} + h⁻_{i+½})/2 · (z⁻_{i+½} −
   z⁺_{i−½})/Δx`` of the same face values, so a lake at rest over any bed
   stays at rest to round-off. In radial geometry the face fluxes are
   weighted by the face radius, the cell by its centre radius, and the hoop
   term ``g h²/(2r)`` is taken as ``g (h⁻²_{i+½} + h⁺²_{i−½})/(4 r_i)``,
   which balances the pressure fluxes of a lake at rest exactly.

Predicted face depths are cut at zero, and near a wet/dry front the
predictor is switched off in cells next to a dry one (their face values are
then those of the plain MUSCL reconstruction, whose mean is the cell value:
the case of Audusse et al.'s positivity bound, Courant number ≤ 1/4).

The ghosted state, the predicted cells, each direction's face fluxes and the
update are separate jitted kernels whose outputs are materialised in
between (:class:`partmesh.gridref.swe.solve.Stepper`): fused into its consumers, XLA:CPU
recomputes a producer for every use.

Velocities are recovered from the momenta with Kurganov & Petrova's (2007)
desingularisation ``u = 2 h (h u)/(h² + max(h², ε²))`` (ε = ``DRY`` m), so a
nearly dry cell cannot produce a large velocity.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.gridref.euler.boundaries import N_GHOST, SchemeAxes, ghost_layer
from partmesh.gridref.euler.reconstruct import LIMITERS, limited_slopes
from partmesh.gridref.grid import cropped
from partmesh.gridref.swe.fluxes import hllc

#: depth [m] below which a cell counts as dry for its velocity (desingularisation ε)
DRY = 1e-6
#: floating-point types a run may use
PRECISIONS = {"float64": jnp.float64, "float32": jnp.float32}


@dataclass(frozen=True)
class Scheme(SchemeAxes):
    """Settings of one shallow-water run."""

    g: float
    dx: tuple[float, ...]
    kinds: tuple[str, ...]  # boundary kind per side, x_lo, x_hi[, y_lo, y_hi] (partmesh.cases.scene.WaterScene.boundary_kinds)
    radial: bool = False
    limiter: str = "mc"
    cfl: float = 0.25


def velocities(U, xp=jnp):
    """Velocities ``(u[, v])`` from ``(h, h u[, h v])``, desingularised;
    ``xp``: the array module (numpy for a frame on the host: no jax
    operation to compile for each new grid size)."""
    h = U[0]
    inverse = 2.0 * h / (h * h + xp.maximum(h * h, DRY * DRY))
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


def _ghost_cells(W, d: int, scheme: Scheme):
    """``(lo, hi)``: per variable of ``W = (h, u[, v], z)``, the ``N_GHOST``
    ghost cells beyond the lower and upper side of direction ``d``."""
    axis, sides = scheme.axes[d], []
    for side, kind in zip(("lo", "hi"), scheme.kinds[2 * d: 2 * d + 2]):
        if kind == "absorbing":
            sides.append(_absorbing(W, axis, side, scheme.g))
        else:
            rule = "reflect" if kind == "axis" else kind
            sides.append(tuple(ghost_layer(a, axis, side, rule, flip=(k == 1 + d)) for k, a in enumerate(W)))
    return sides


def with_ghosts(W, scheme: Scheme):
    """``(h, u[, v], z)`` padded with ``N_GHOST`` ghost cells on every side;
    a corner takes the rule of y applied to the ghost cells of x (the rules
    act on rows and columns apart, so the order does not matter). The
    interior is padded once and the ghost cells written into it: XLA:CPU
    joins arrays by ``concatenate`` several times slower."""
    ng, axes = N_GHOST, scheme.axes
    out = [jax.lax.pad(a, jnp.zeros((), a.dtype), [(ng, ng, 0)] * a.ndim) for a in W]
    for d, axis in enumerate(axes):
        for side, cells in zip(("lo", "hi"), _ghost_cells(W, d, scheme)):
            for e in range(d):  # the corners
                lo, hi = _ghost_cells(cells, e, scheme)
                cells = tuple(jnp.concatenate(abc, axis=axes[e]) for abc in zip(lo, cells, hi))
            start = [0 if b in axes[:d] else ng for b in range(len(axes))]
            start[axis] = 0 if side == "lo" else W[0].shape[axis] + ng
            out = [jax.lax.dynamic_update_slice(o, c, start) for o, c in zip(out, cells)]
    return tuple(out)


def ghosted(U, z, scheme: Scheme):
    """``(h, u[, v], z)`` of the state ``U`` over the bed ``z``, with ghost cells."""
    return with_ghosts((U[0], *velocities(U), z), scheme)


def _trimmed(a, axis, lo, hi):
    """``a`` without ``lo`` entries at the start and ``hi`` at the end of ``axis``."""
    return jax.lax.slice_in_dim(a, lo, a.shape[axis] - hi, axis=axis)


def _across(upper, lower, axis):
    """Per cell, the face quantity ``upper`` at its upper face minus
    ``lower`` at its lower face (both given on all faces)."""
    return _trimmed(upper, axis, 1, 0) - _trimmed(lower, axis, 0, 1)


def _ghost_radii(radius, dx):
    """The centre radii of the cells of a radial run with one ghost cell at each end."""
    r_c = radius[0]
    return jnp.concatenate([r_c[:1] - dx, r_c, r_c[-1:] + dx])


def predicted(Wg, dt, scheme: Scheme, radius=None):
    """``(h̃, ũ[, ṽ], z, slopes)`` of every cell but the outer ghost ring: the
    centre values half a step on (step 2 of the module docstring) and, per
    direction, the limited slopes ``(Δh, Δη, Δu[, Δv])`` (step 1). The
    predictor is off in cells that have a dry neighbour."""
    g, axes = scheme.g, scheme.axes
    h, *vel, z = Wg
    limiter = LIMITERS[scheme.limiter]
    slopes = [[cropped(limited_slopes(a, axis, limiter), [b for b in axes if b != axis]) for a in (h, h + z, *vel)]
              for axis in axes]
    slopes = jax.lax.optimization_barrier(slopes)  # once, not again for every use below
    hc, zc = cropped(h, axes), cropped(z, axes)
    vc = [cropped(v, axes) for v in vel]
    rate_h = -sum((vc[d] * S[0] + hc * S[2 + d]) / dx for d, (S, dx) in enumerate(zip(slopes, scheme.dx)))
    if radius is not None:
        rate_h = rate_h - hc * vc[0] / _ghost_radii(radius, scheme.dx[0])
    rate_v = [-sum(vc[d] * S[2 + k] / dx for d, (S, dx) in enumerate(zip(slopes, scheme.dx)))
              - g * slopes[k][1] / scheme.dx[k] for k in range(scheme.dim)]
    wet, around = h > DRY, cropped(h > DRY, axes)
    for axis in axes:
        others = [b for b in axes if b != axis]
        around = around & cropped(_trimmed(wet, axis, 0, 2), others) & cropped(_trimmed(wet, axis, 2, 0), others)
    half = jnp.where(around, 0.5 * dt, 0.0)
    return (hc + half * rate_h, *(v + half * r for v, r in zip(vc, rate_v)), zc, slopes)


def _face_states(P, d: int):
    """``(upper, lower)``: the values ``(h, z, u[, v])`` at the upper and
    lower face along direction ``d`` of each predicted cell ``P``."""
    h, *vel, z, slopes = P
    dh, deta, *dv = slopes[d]
    dz = 0.5 * (deta - dh)
    upper = (jnp.maximum(h + 0.5 * dh, 0.0), z + dz, *(v + 0.5 * s for v, s in zip(vel, dv)))
    lower = (jnp.maximum(h - 0.5 * dh, 0.0), z - dz, *(v - 0.5 * s for v, s in zip(vel, dv)))
    return upper, lower


def _along(P, d: int, scheme: Scheme):
    """The predicted cells ``P`` cropped to the interior across direction
    ``d`` (one ghost cell left at each end along it)."""
    others = [axis for k, axis in enumerate(scheme.axes) if k != d]
    h, *vel, z, slopes = P
    return (*(cropped(a, others) for a in (h, *vel, z)), [[cropped(a, others) for a in S] for S in slopes])


def face_fluxes(P, d: int, scheme: Scheme):
    """``(mass, normal momentum from the left, from the right, tangential
    momentum)`` through the faces normal to direction ``d`` of the interior,
    from the predicted cells ``P``: the HLLC flux of the hydrostatically
    reconstructed states, its normal momentum corrected by g (h±² − h*±²)/2
    on each side (step 3 of the module docstring)."""
    g, axis = scheme.g, scheme.axes[d]
    upper, lower = _face_states(_along(P, d, scheme), d)
    # face j lies between cells j and j + 1 of these rows: left state from upper, right from lower
    (hL, zL, *velL), (hR, zR, *velR) = ([_trimmed(a, axis, 0, 1) for a in upper],
                                        [_trimmed(a, axis, 1, 0) for a in lower])
    z_face = jnp.maximum(zL, zR)
    hL_star, hR_star = jnp.maximum(0.0, hL + zL - z_face), jnp.maximum(0.0, hR + zR - z_face)
    tangential_L = velL[1 - d] if scheme.dim == 2 else jnp.zeros_like(hL)
    tangential_R = velR[1 - d] if scheme.dim == 2 else jnp.zeros_like(hR)
    mass, mom_n, mom_t = hllc(hL_star, velL[d], tangential_L, hR_star, velR[d], tangential_R, g)
    from_left = mom_n + 0.5 * g * (hL * hL - hL_star * hL_star)    # the flux cell j sees at its upper face
    from_right = mom_n + 0.5 * g * (hR * hR - hR_star * hR_star)   # the flux cell j + 1 sees at its lower face
    return mass, from_left, from_right, mom_t


def direction_terms(P, fluxes, d: int, scheme: Scheme, radius=None):
    """The part of ``dU/dt`` (one array per component of ``U``) that the faces
    normal to direction ``d`` give, from their :func:`face_fluxes`: flux
    differences, the bed source and, radially, the hoop term (step 4 of the
    module docstring); ``radius``: the cell-centre and face radii ``(r_c, r_f)``
    of a radial run."""
    g, dim, axes = scheme.g, scheme.dim, scheme.axes
    mass, from_left, from_right, mom_t = fluxes
    (h_up, z_up, *_), (h_lo, z_lo, *_) = (tuple(cropped(a, axes) for a in side) for side in _face_states(P, d))
    inv_dx = 1.0 / scheme.dx[d]
    source = -0.5 * g * (h_lo + h_up) * (z_up - z_lo) * inv_dx
    face, cell = radius[::-1] if radius is not None else (1.0, 1.0)  # radial: face and centre radii
    axis = axes[d]
    out = [jnp.zeros_like(h_up) for _ in range(dim + 1)]
    out[0] = -_across(face * mass, face * mass, axis) * inv_dx / cell
    out[1 + d] = -_across(face * from_left, face * from_right, axis) * inv_dx / cell + source
    if radius is not None:
        out[1 + d] = out[1 + d] + 0.25 * g * (h_up * h_up + h_lo * h_lo) / cell  # the hoop term
    if dim == 2:
        out[2 - d] = -_across(mom_t, mom_t, axis) * inv_dx
    return tuple(out)


def updated(U, P, fluxes, dt, scheme: Scheme, radius=None):
    """``Uⁿ⁺¹ = Uⁿ + Δt Σ_d`` :func:`direction_terms` (``fluxes``: one
    :func:`face_fluxes` per direction)."""
    parts = [direction_terms(P, F, d, scheme, radius) for d, F in enumerate(fluxes)]
    return tuple(u + dt * sum(p[k] for p in parts) for k, u in enumerate(U))


def hancock_step(U, z, dt, scheme: Scheme, radius=None):
    """``U`` after one MUSCL–Hancock step of ``dt`` (module docstring), in
    one function (the solver runs the same kernels as a pipeline,
    :class:`partmesh.gridref.swe.solve.Stepper`)."""
    P = predicted(ghosted(U, z, scheme), dt, scheme, radius)
    return updated(U, P, [face_fluxes(P, d, scheme) for d in range(scheme.dim)], dt, scheme, radius)


def stable_dt(U, scheme: Scheme):
    """``Δt = C / max Σ_d (|u_d| + sqrt(g h))/Δx_d`` over the wet cells; NaN
    if a depth is negative or a value not finite (the caller reports where)."""
    h = U[0]
    c = jnp.sqrt(scheme.g * jnp.maximum(h, 0.0))
    rate = sum((jnp.abs(v) + c) / dx for v, dx in zip(velocities(U), scheme.dx))
    bad = (h < 0.0) | ~jnp.isfinite(rate) | ~jnp.all(jnp.stack([jnp.isfinite(a) for a in U]), axis=0)
    return jnp.where(jnp.any(bad), jnp.nan, scheme.cfl / jnp.maximum(jnp.max(rate), jnp.finfo(h.dtype).tiny))


def radii(x_centres, dx, dtype=jnp.float64):
    """Cell-centre and face radii ``(r_c, r_f)`` of a radial grid."""
    r_c = np.asarray(x_centres, float)
    r_f = np.concatenate([r_c - 0.5 * dx, r_c[-1:] + 0.5 * dx])
    return jnp.asarray(r_c.astype(dtype)), jnp.asarray(r_f.astype(dtype))
