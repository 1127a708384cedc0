r"""Rigid walls and obstacles for gas SPH: the skew-gradient wall treatment
(SPEC §3.1, "Boundaries") of Prasanna Kumar, Patnaik & Ramamurthi (2018),
Phys. Fluids 30, 046105.

Particles
---------
* **Wall particles** ``w`` sit on the surface of every obstacle at spacing
  ``Δx/2`` with the outward (solid → fluid) unit normal ``n̂_w``; points
  outside the particle box, on a side of the box facing out of it (the base
  of a wedge standing on the floor), or inside another obstacle are
  dropped. They carry no mass; they only hold the wall state.
* **Virtual particles** ``v`` are the points of the fluid lattice
  ``x = x0 + (i + ½) s_x``, ``y = y0 + (j + ½) s_y`` (the lattice of
  :func:`partmesh.particle.sph.particles.place_2d`, ``s = L/round(L/Δx)`` per axis)
  that lie inside an obstacle within ``depth`` of its surface,
  ``−depth ≤ φ ≤ 0`` (``φ`` the union signed distance), inside the particle
  box (beyond a side of the box the side's ghosts, mirrored from fluid and
  virtual particles alike, stand in). Fluid (``φ > 0``) and virtual
  points together are the complete lattice (less the few points near a
  corner sharper than a right angle that :func:`off_surface` drops), so the
  initial summation density is uniform across the surface. Each has the
  volume ``V_v = s_x s_y`` and is tied to its nearest wall particle
  (``anchor``), offset ``d = x_v − x_w``.

Wall state (every step)
-----------------------
With the skewed kernel ``W_s(r, H) = W(|r|, H) (1 + erf(λ·r/H))``,
``λ = −c n̂_w`` (c = 10), evaluated at ``r = x_w − x_j`` with the fluid
particle's own support ``H_j`` (particle j contributes when
``|x_w − x_j| < H_j``) and ``V_j = m_j/ρ_j``:

.. math::

    \bar φ_w = \frac{Σ_j V_j φ_j W_s}{Σ_j V_j W_s}, \qquad
    \bar x_w = \frac{Σ_j V_j x_j W_s}{Σ_j V_j W_s}, \\
    ∇φ_w = M^{-1} Σ_j V_j (φ_j − \bar φ_w) ∇W_s, \qquad
    M = Σ_j V_j ∇W_s ⊗ (x_j − \bar x_w), \\
    φ_w = \bar φ_w + ∇φ_w · (x_w − \bar x_w)

for ``φ = ρ, p, v_x, v_y`` (``∇W_s`` the gradient with respect to ``r``,
:func:`partmesh.particle.kernels.skewed_grad`; ``M_ab = Σ V ∂_a W_s (x_j − x̄)_b``).
The Shepard value ``φ̄_w`` of a linear field is exact at the kernel centroid
``x̄_w`` (not at ``x_w``: the one-sided, skewed weights put ``x̄_w`` inside
the fluid), and with ``x̄_w`` as the reference point ``Σ V (φ_j − φ̄) ∇W_s
= M ∇φ`` exactly, so value and gradient at ``x_w`` reproduce any linear
field to round-off (first-order consistency). The skewing switches off
fluid particles on the solid side of the wall (the far side of a thin body,
round a sharp apex): their weight falls as ``1 + erf(−10 δ/H)`` with the
depth ``δ`` behind the wall plane.

* ``|det M| ≤ 10⁻⁶ ‖M‖²_F`` (too few or collinear neighbours): zero
  gradient, ``φ_w = φ̄_w``.
* No fluid particle reaches ``w`` (zero total weight): ``φ_w`` is the state
  of the nearest fluid particle, zero gradient.
* Positivity: for ρ and p the correction ``δ`` (centroid → wall) is
  limited to ``−½ φ ≤ δ ≤ φ``, so the corrected value stays within
  ``[½ φ, 2 φ]`` of the value it corrects.

Virtual state (every step)
--------------------------
For the virtual particle ``v`` of anchor ``w`` and offset ``d``, the
Taylor expansion about the wall particle is taken at the virtual particle's
mirror image across the wall's tangent, offset ``d_m = d − 2 (d·n̂_w) n̂_w``
(the fluid state a plane-wall mirror ghost would carry, so the wall is a
symmetry plane of pressure and density to first order):
``ρ_v = ρ_w + ∇ρ_w·d_m``, ``p_v = p_w + ∇p_w·d_m``,
``v_m = v_w + (∇v_w)·d_m`` and the slip-wall mirror about the anchor's
normal ``v_v = v_m − 2 (v_m·n̂_w) n̂_w``, so fluid approaching the wall meets
virtual particles approaching it from the other side; mass
``m_v = ρ_v V_v``, support ``H_v = η √V_v`` and ``u_v = p_v / ((γ − 1) ρ_v)``.

Bounds: ``ρ_v``, ``p_v/ρ_v`` and each component of ``v_m`` are clipped to
the range of that quantity over the fluid particles in front of the anchor
(those reaching it from the fluid side of its tangent, ``(x_j − x_w)·n̂_w ≥
0``; where none is in front, all that reach it), the local-extremum bound of
MUSCL limiters (Barth & Jespersen 1989, AIAA 89-0366) applied to the
extrapolation. Linear ρ, p and v are untouched where the mirror image lies
within the convex hull of those particles (a linear function and a ratio
of two, p/ρ, take their extremes over a convex set at its corners); what
the bounds stop is a wall acting as a source.
Extrapolated apart, ρ and p may each be off by a factor of a few where the
gradients are steep and one-sided (behind the apex of an obstacle in a
strong blast, where the wake is near vacuum), and a virtual particle hotter
than every fluid particle near it heats them (artificial conduction,
compression by virtual velocities far above the fluid's), which raises the
wall state in turn: the run runs away.

:func:`reflect_into_fluid` is the safeguard that no particle ends a step
inside a solid: it mirrors such a particle across the surface.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
from numba import prange
from scipy.spatial import cKDTree

from partmesh.cases.errors import InputError
from partmesh.cases.shapes import Shape
from partmesh.compare.checks import positive
from partmesh.particle.kernels import kernel_id, skewed_grad, skewed_w
from partmesh.particle.neighbours import cell_grid, counting_sort

__all__ = [
    "SKEW",
    "Wall",
    "in_box",
    "lattice_coordinate",
    "nearest_wall",
    "off_surface",
    "points_within_support",
    "reflect_into_fluid",
    "virtual_lattice",
    "virtual_state",
    "wall_particles",
    "wall_state",
    "walls",
]

#: c in the skewness λ = −c n̂ (Prasanna Kumar et al. 2018).
SKEW = 10.0

# |det M| below this fraction of ‖M‖²_F counts as singular (zero gradient)
_SINGULAR = 1e-6
# ρ and p (the first two wall fields) are positive and limited
_N_POSITIVE = 2
# mirror passes before reflect_into_fluid falls back to the surface point
_REFLECT_PASSES = 4


@dataclass(frozen=True, eq=False)
class Wall:
    """Wall and virtual particles of the obstacles, built once per run by
    :func:`walls`; nothing in it changes during the run.

    Attributes
    ----------
    x_wall, normal_wall : (n_w, 2)
        Wall-particle positions and outward (solid → fluid) unit normals.
    x_virtual : (n_v, 2)
        Virtual-particle positions (lattice points inside the obstacles).
    anchor : (n_v,) int64
        Index of each virtual particle's nearest wall particle.
    offset : (n_v, 2)
        ``d = x_virtual − x_wall[anchor]``.
    volume : (n_v,)
        Virtual-particle volume ``V_v = s_x s_y``.
    lo, period : (2,)
        The box's lower corner and its period along each axis (0 where the
        axis is not periodic): fluid particles near a periodic side reach
        the wall particles across it through their periodic images, so the
        two parts of an obstacle cut by the side act as one body.
    """

    x_wall: np.ndarray
    normal_wall: np.ndarray
    x_virtual: np.ndarray
    anchor: np.ndarray
    offset: np.ndarray
    volume: np.ndarray
    lo: np.ndarray
    period: np.ndarray


# --------------------------------------------------------------------------
# setup
# --------------------------------------------------------------------------


def walls(scene, dx, depth, box=None) -> Wall | None:
    """The wall and virtual particles of ``scene.obstacles`` (None without
    obstacles).

    ``dx`` is the fluid lattice spacing (wall particles are ``dx/2`` apart),
    ``depth`` how far inside the solid virtual particles reach (at least the
    largest support radius, so that the fluid's kernels are complete).
    ``box`` is the region the fluid lattice fills, ``((x0, x1), (y0, y1))``,
    exactly as passed to :func:`partmesh.particle.sph.particles.place_2d` (default
    ``scene.domain``); the virtual particles are points of the same lattice.
    The nearest-wall search is one k-d tree query (O(n log n), setup only).
    Along the scene's periodic axes (``scene.periodic``, if it has them)
    an obstacle cut by a side joins its other part across it: a virtual
    particle may be anchored to a wall particle across the side (its
    offset to the nearest image), and the wall state sees the fluid
    across it (:attr:`Wall.period`).
    """
    obstacles = tuple(scene.obstacles)
    if not obstacles:
        return None
    dx = positive("dx", dx)
    depth = positive("depth", depth)
    box = _as_box(scene.domain if box is None else box)
    if any(not isinstance(s, Shape) for s in obstacles):
        raise InputError("scene.obstacles must hold partmesh.cases.shapes.Shape objects.")
    periodic = getattr(scene, "periodic", (False, False))
    period = np.array([hi - lo if wraps else 0.0 for (lo, hi), wraps in zip(box, periodic)])
    x_wall, normal_wall = wall_particles(obstacles, dx, box)
    x_virtual, volume = virtual_lattice(obstacles, dx, depth, box)
    if len(x_wall) == 0:
        x_virtual, volume = x_virtual[:0], volume[:0]
    images, source = periodic_images(x_wall, box[:, 0], period, depth + dx)
    nearest = nearest_wall(images, x_virtual)
    anchor = source[nearest]
    offset = x_virtual - images[nearest]
    arrays = (x_wall, normal_wall, x_virtual, anchor, offset, volume, box[:, 0].copy(), period)
    for a in arrays:
        a.setflags(write=False)
    return Wall(*arrays)


def periodic_images(x, lo, period, reach) -> tuple[np.ndarray, np.ndarray]:
    """The points ``x`` (n, 2) followed by their images across every
    periodic side they are within ``reach`` of (``period`` > 0 along that
    axis, the box starting at ``lo``; corners get the image across both
    sides), and each point's source index."""
    source = np.arange(len(x))
    for axis in np.flatnonzero(period > 0.0):
        near_lo = x[:, axis] < lo[axis] + reach
        near_hi = x[:, axis] > lo[axis] + period[axis] - reach
        shift = np.zeros(2)
        shift[axis] = period[axis]
        x = np.concatenate([x, x[near_lo] + shift, x[near_hi] - shift])
        source = np.concatenate([source, source[near_lo], source[near_hi]])
    return x, source


def _as_box(box) -> np.ndarray:
    try:
        b = np.asarray(box, dtype=float)
    except (TypeError, ValueError):
        raise InputError("box must be ((x0, x1), (y0, y1)) with finite numbers.") from None
    if b.shape != (2, 2) or not np.all(np.isfinite(b)) or np.any(b[:, 1] <= b[:, 0]):
        raise InputError(f"box must be ((x0, x1), (y0, y1)) with x0 < x1 and y0 < y1 (obstacles are 2D); "
                         f"got {box!r}.")
    return b


def _union_distance(shapes, x, y) -> np.ndarray:
    """Signed distance of the union of ``shapes``, each shape evaluated only
    at the points in its bounding box (+inf outside every box, where only
    the sign matters: outside the solids)."""
    phi = np.full(x.shape, np.inf)
    for s in shapes:
        x0, y0, x1, y1 = s.bounds()
        near = np.flatnonzero((x >= x0) & (x <= x1) & (y >= y0) & (y <= y1))
        if near.size:
            phi[near] = np.minimum(phi[near], s.signed_distance(x[near], y[near]))
    return phi


def in_box(p, box, tol=0.0) -> np.ndarray:
    """True for the points ``p`` (n, dim) within ``box`` ((lo, hi) per axis),
    widened by ``tol``."""
    box = np.asarray(box, dtype=float)
    return np.all((p >= box[:, 0] - tol) & (p <= box[:, 1] + tol), axis=1)


def wall_particles(obstacles, dx, box) -> tuple[np.ndarray, np.ndarray]:
    """Surface points ``(n_w, 2)`` of every obstacle at spacing ``dx/2`` and
    their outward normals, keeping the points inside ``box`` (within
    ``10⁻⁶ dx``) whose normal does not point out of it (a face lying on a
    side of the box, such as the base of a wedge on the floor, has no fluid
    in front of it) and outside every other obstacle (``φ > 0``)."""
    tol = 1e-6 * dx
    pts, nrm = [], []
    for k, shape in enumerate(obstacles):
        p, n = shape.surface_points(0.5 * dx)
        keep = in_box(p, box, tol) & in_box(p + 1e-3 * dx * n, box, tol)
        others = obstacles[:k] + obstacles[k + 1:]
        keep &= _union_distance(others, p[:, 0], p[:, 1]) > 0.0
        pts.append(p[keep])
        nrm.append(n[keep])
    return np.concatenate(pts), np.concatenate(nrm)


def lattice_coordinate(lo, hi, n, i):
    """Coordinate of lattice index ``i`` along an axis ``[lo, hi]`` cut into
    ``n`` cells: ``lo + (i + ½)(hi − lo)/n`` (the arithmetic of ``place_2d``;
    ``i`` may lie outside ``[0, n)``)."""
    return lo + (np.asarray(i) + 0.5) * (hi - lo) / n


def virtual_lattice(obstacles, dx, depth, box) -> tuple[np.ndarray, np.ndarray]:
    """Lattice points ``(n_v, 2)`` of ``box`` with ``−depth ≤ φ ≤ 0``, each
    once, and their volumes ``s_x s_y``."""
    n = np.maximum(np.rint((box[:, 1] - box[:, 0]) / dx).astype(np.int64), 1)
    s = (box[:, 1] - box[:, 0]) / n
    first, last = np.zeros(2, np.int64), n - 1  # the lattice range of the box
    keys = []
    for shape in obstacles:
        b = np.asarray(shape.bounds()).reshape(2, 2).T  # ((x0, x1), (y0, y1))
        lo = np.maximum(np.floor((b[:, 0] - box[:, 0]) / s - 0.5).astype(np.int64), first)
        hi = np.minimum(np.ceil((b[:, 1] - box[:, 0]) / s - 0.5).astype(np.int64), last)
        if np.any(hi < lo):
            continue
        i, j = np.meshgrid(np.arange(lo[0], hi[0] + 1), np.arange(lo[1], hi[1] + 1), indexing="ij")
        keys.append((i.ravel() - first[0]) * (last[1] - first[1] + 1) + (j.ravel() - first[1]))
    key = np.unique(np.concatenate(keys)) if keys else np.zeros(0, np.int64)
    i, j = key // (last[1] - first[1] + 1) + first[0], key % (last[1] - first[1] + 1) + first[1]
    x = lattice_coordinate(box[0, 0], box[0, 1], n[0], i)
    y = lattice_coordinate(box[1, 0], box[1, 1], n[1], j)
    phi = _union_distance(obstacles, x, y)
    keep = (phi <= 0.0) & (phi >= -depth)
    pts = off_surface(obstacles, np.stack([x[keep], y[keep]], axis=1), 0.5 * dx)
    return pts, np.full(len(pts), s[0] * s[1])


def off_surface(obstacles, x, gap) -> np.ndarray:
    """``x`` (n, 2) with every point closer than ``gap`` to an obstacle's
    surface moved along the normal to exactly ``gap`` from it, on its own
    side (``φ = 0`` counts as inside). Lattice points of a slanted or curved
    surface lie at any distance from it; moved off it by half a spacing,
    fluid and virtual particles start at least one spacing apart across
    the wall, as on a wall aligned with the lattice, and no fluid particle
    sliding along the wall meets a virtual one at the surface.

    Near a corner sharper than a right angle a move along one face's
    normal may carry a point across the other face (a point just inside
    the 60° corner of a triangle, moved off its base, leaves through its
    slanted face); such a point is dropped: the returned points are those
    that stayed on their side, ``(m, 2)``, m ≤ n."""
    x = np.array(x, dtype=float)
    inside = _union_distance(obstacles, x[:, 0], x[:, 1]) <= 0.0
    for shape in obstacles:
        phi = shape.signed_distance(x[:, 0], x[:, 1])
        near = np.flatnonzero(np.abs(phi) < gap)
        if near.size:
            nx, ny = shape.normal(x[near, 0], x[near, 1])
            shift = np.where(phi[near] > 0.0, gap, -gap) - phi[near]
            x[near, 0] += shift * nx
            x[near, 1] += shift * ny
    return x[(_union_distance(obstacles, x[:, 0], x[:, 1]) <= 0.0) == inside]


def nearest_wall(x_wall, x_virtual) -> np.ndarray:
    """Index (int64) of the nearest wall particle of every virtual particle."""
    if len(x_virtual) == 0:
        return np.zeros(0, dtype=np.int64)
    _, idx = cKDTree(x_wall).query(x_virtual)
    return np.asarray(idx, dtype=np.int64)


# --------------------------------------------------------------------------
# points-vs-particles search
# --------------------------------------------------------------------------


@numba.njit(cache=True)
def _cell_of(p, origin, width, n):
    c = math.floor((p - origin) / width)
    return min(max(c, 0), n - 1)


@numba.njit(cache=True, parallel=True)
def _support_pass(points, xs, Hs, start, origin, width, ncell, offsets, index, dx, order, fill):
    """Per point, the particles j (cell-sorted ``xs``, ``Hs``) with
    ``|p − x_j| < H_j`` in the 3×3 cells around the point's cell. ``fill``
    False: return the counts; True: write them at ``offsets`` (original ids
    via ``order``, ``dx = p − x_j``)."""
    m = points.shape[0]
    counts = np.zeros(m, dtype=np.int64)
    for k in prange(m):
        px, py = points[k, 0], points[k, 1]
        cx = _cell_of(px, origin[0], width[0], ncell[0])
        cy = _cell_of(py, origin[1], width[1], ncell[1])
        q = offsets[k] if fill else 0
        c = 0
        for yc in range(max(cy - 1, 0), min(cy + 2, ncell[1])):
            row = yc * ncell[0]
            for t in range(start[row + max(cx - 1, 0)], start[row + min(cx + 2, ncell[0])]):
                ex = px - xs[t, 0]
                ey = py - xs[t, 1]
                if ex * ex + ey * ey < Hs[t] * Hs[t]:
                    if fill:
                        index[q + c] = order[t]
                        dx[q + c, 0] = ex
                        dx[q + c, 1] = ey
                    c += 1
        counts[k] = c
    return counts


def points_within_support(points, x, H) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For every point ``p_k`` (2D), the particles ``j`` with
    ``|p_k − x_j| < H_j`` (each particle's own support), as CSR lists
    ``(offsets, index, dx)``: point k's particles are
    ``index[offsets[k]:offsets[k+1]]``, ``dx = p_k − x_j``.

    Cell list with cells ``≥ max H`` wide over the bounding box of points and
    particles, stable counting sort of the particles (O(N)), 3×3 stencil per
    point: O(N + points · neighbours). No periodic images.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    x = np.ascontiguousarray(x, dtype=np.float64)
    H = np.ascontiguousarray(H, dtype=np.float64)
    m = len(points)
    if m == 0 or len(x) == 0:
        return np.zeros(m + 1, np.int64), np.zeros(0, np.int64), np.zeros((0, 2))
    lo = np.minimum(points.min(axis=0), x.min(axis=0))
    hi = np.maximum(points.max(axis=0), x.max(axis=0))
    origin, width, ncell, _, _ = cell_grid(x, lo, hi, (False, False), float(H.max()))
    cid = (np.clip(np.floor((x[:, 0] - origin[0]) / width[0]), 0, ncell[0] - 1).astype(np.int64)
           + ncell[0] * np.clip(np.floor((x[:, 1] - origin[1]) / width[1]), 0, ncell[1] - 1).astype(np.int64))
    start, order = counting_sort(cid, int(ncell[0] * ncell[1]))
    xs, Hs = x[order], H[order]
    grid = (xs, Hs, start, origin[:2], width[:2], ncell[:2])
    none = np.zeros(0, np.int64)
    counts = _support_pass(points, *grid, none, none, np.zeros((0, 2)), order, False)
    offsets = np.concatenate([[0], np.cumsum(counts)])
    index = np.empty(offsets[-1], dtype=np.int64)
    dx = np.empty((offsets[-1], 2))
    _support_pass(points, *grid, offsets, index, dx, order, True)
    return offsets, index, dx


# --------------------------------------------------------------------------
# wall and virtual state
# --------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _limited(phi, delta):
    """Correction ``delta`` to the positive value ``phi`` clipped to
    ``[−½ phi, phi]`` (no correction if ``phi ≤ 0``)."""
    if phi <= 0.0:
        return 0.0
    return min(max(delta, -0.5 * phi), phi)


@numba.njit(cache=True, inline="always")
def _spanned(state, f):
    """Field ``f`` of the fields a virtual particle is bounded in, ``(ρ, p/ρ,
    v_x, v_y)``, of the fluid state ``(ρ, p, v_x, v_y)``."""
    return state[1] / state[0] if f == 1 else state[f]


@numba.njit(cache=True, inline="always")
def _widen(span, state):
    """Widen the ranges ``span (4, 2)`` of :func:`_spanned`'s fields to hold ``state``."""
    for f in range(span.shape[0]):
        value = _spanned(state, f)
        span[f, 0] = min(span[f, 0], value)
        span[f, 1] = max(span[f, 1], value)


@numba.njit(cache=True, parallel=True)
def _wall_fields(kind, normal, offsets, index, dx, fields, V, H, c):
    """Skewed-kernel Shepard values moved to the wall point with the corrected
    gradient (module docstring); ``reached[w]`` False where the total weight
    is zero (values and gradients then left at 0)."""
    nw = normal.shape[0]
    nf = fields.shape[1]
    value = np.zeros((nw, nf))
    grad = np.zeros((nw, nf, 2))
    reached = np.zeros(nw, dtype=np.bool_)
    span = np.empty((nw, nf, 2))  # per field of _spanned: its range over the fluid in front
    for w in prange(nw):
        lx = -c * normal[w, 0]
        ly = -c * normal[w, 1]
        a, b = offsets[w], offsets[w + 1]
        total = 0.0
        cx = 0.0
        cy = 0.0
        for f in range(nf):
            span[w, f, 0] = np.inf
            span[w, f, 1] = -np.inf
        for q in range(a, b):
            j = index[q]
            wq = V[j] * skewed_w(kind, dx[q, 0], dx[q, 1], H[j], 2, lx, ly)
            total += wq
            cx -= wq * dx[q, 0]  # x_j − x_w = −dx
            cy -= wq * dx[q, 1]
            for f in range(nf):
                value[w, f] += wq * fields[j, f]
            if wq > 0.0 and dx[q, 0] * normal[w, 0] + dx[q, 1] * normal[w, 1] <= 0.0:  # (x_j − x_w)·n̂ ≥ 0
                _widen(span[w], fields[j])
        if not total > 0.0:
            for f in range(nf):
                value[w, f] = 0.0
            continue
        reached[w] = True
        if span[w, 0, 0] > span[w, 0, 1]:  # no fluid in front, only the erf tail behind: its range
            for q in range(a, b):
                _widen(span[w], fields[index[q]])
        cx /= total
        cy /= total
        for f in range(nf):
            value[w, f] /= total
        m00 = 0.0
        m01 = 0.0
        m10 = 0.0
        m11 = 0.0
        for q in range(a, b):
            j = index[q]
            gx, gy = skewed_grad(kind, dx[q, 0], dx[q, 1], H[j], 2, lx, ly)
            gx *= V[j]
            gy *= V[j]
            ex = -dx[q, 0] - cx  # x_j − x̄_w
            ey = -dx[q, 1] - cy
            m00 += gx * ex
            m01 += gx * ey
            m10 += gy * ex
            m11 += gy * ey
            for f in range(nf):
                d = fields[j, f] - value[w, f]
                grad[w, f, 0] += d * gx
                grad[w, f, 1] += d * gy
        det = m00 * m11 - m01 * m10
        if not abs(det) > _SINGULAR * (m00 * m00 + m01 * m01 + m10 * m10 + m11 * m11):
            for f in range(nf):
                grad[w, f, 0] = 0.0
                grad[w, f, 1] = 0.0
            continue
        for f in range(nf):
            b0 = grad[w, f, 0]
            b1 = grad[w, f, 1]
            g0 = (m11 * b0 - m01 * b1) / det
            g1 = (m00 * b1 - m10 * b0) / det
            grad[w, f, 0] = g0
            grad[w, f, 1] = g1
            delta = -(g0 * cx + g1 * cy)  # ∇φ · (x_w − x̄_w)
            value[w, f] += _limited(value[w, f], delta) if f < _N_POSITIVE else delta
    return value, grad, reached, span


def _fluid_arrays(x, v, rho, p, m, H):
    """Validated fluid arrays: positions (n, 2), fields (n, 4) = (ρ, p, v_x,
    v_y), volumes m/ρ and supports H."""
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    if x.shape != (n, 2) or n == 0:
        raise InputError(f"x must hold the fluid positions with shape (n, 2), n >= 1; got shape {x.shape}.")
    v = np.asarray(v, dtype=np.float64)
    if v.shape != (n, 2):
        raise InputError(f"v must have shape ({n}, 2) like x; got shape {v.shape}.")
    cols = {}
    for name, a in (("rho", rho), ("p", p), ("m", m), ("H", H)):
        a = np.asarray(a, dtype=np.float64)
        if a.shape != (n,):
            raise InputError(f"{name} must have shape ({n},), one value per fluid particle; got {a.shape}.")
        cols[name] = a
    for name in ("rho", "m", "H"):
        if not np.all(cols[name] > 0):
            raise InputError(f"{name} must be > 0 for every fluid particle.")
    fields = np.column_stack([cols["rho"], cols["p"], v])
    return np.ascontiguousarray(x), fields, cols["m"] / cols["rho"], np.ascontiguousarray(cols["H"])


def wall_state(wall, x, v, rho, p, m, H, kind, skew=SKEW) -> tuple[np.ndarray, np.ndarray]:
    """Values ``(n_w, 4)`` and gradients ``(n_w, 4, 2)`` of ``(ρ, p, v_x, v_y)``
    at the wall particles, from the fluid particles ``x (n, 2)``, ``v (n, 2)``,
    ``rho, p, m, H (n,)`` (``H`` the compact support radius): skewed-kernel
    Shepard value and first-order-consistent gradient (module docstring),
    ``gradients[w, f] = ∇φ_f``. ``kind`` is a kernel name or id
    (:data:`partmesh.particle.kernels.KERNELS`); ``skew`` the c of ``λ = −c n̂``
    (0 gives the plain kernel). A wall particle no fluid particle reaches
    takes the state of the nearest fluid particle, with zero gradient.
    """
    return _state_at_walls(wall, x, v, rho, p, m, H, kind, skew)[:2]


def _state_at_walls(wall, x, v, rho, p, m, H, kind, skew):
    """:func:`wall_state`'s values and gradients and ``span (n_w, 4, 2)``,
    the smallest and largest ρ, p/ρ, v_x and v_y of the fluid particles in
    front of each wall particle (on the fluid side of its tangent, within
    their supports; all that reach it where none is in front; the nearest
    one's where none reaches)."""
    if not isinstance(wall, Wall):
        raise InputError("wall must be the Wall returned by walls().")
    kind = kernel_id(kind)
    skew = float(skew)
    if not (math.isfinite(skew) and skew >= 0):
        raise InputError(f"skew must be a finite number >= 0; got {skew!r}.")
    x, fields, V, H = _fluid_arrays(x, v, rho, p, m, H)
    if np.any(wall.period > 0.0):  # the fluid across a periodic side, as its images
        x, source = periodic_images(x, wall.lo, wall.period, float(H.max()))
        fields, V, H = fields[source], V[source], H[source]
    offsets, index, dx = points_within_support(wall.x_wall, x, H)
    value, grad, reached, span = _wall_fields(kind, wall.normal_wall, offsets, index, dx, fields, V, H, skew)
    lost = np.flatnonzero(~reached)
    if lost.size:
        _, j = cKDTree(x).query(wall.x_wall[lost])
        value[lost] = fields[j]
        nearest = fields[j].copy()
        nearest[:, 1] /= nearest[:, 0]
        span[lost] = nearest[:, :, None]
    return value, grad, span


@numba.njit(cache=True, inline="always")
def _clipped(value, bounds):
    """``value`` clipped to ``[bounds[0], bounds[1]]``."""
    return min(max(value, bounds[0]), bounds[1])


@numba.njit(cache=True, parallel=True)
def _extrapolated(value, grad, span, anchor, offset, normal, volume, eta, gamma):
    """Virtual particles' velocity, density, specific energy, support and mass
    by the Taylor expansion about their anchors, evaluated at their mirror
    images (module docstring)."""
    nv = anchor.shape[0]
    vel = np.empty((nv, 2))
    rho = np.empty(nv)
    u = np.empty(nv)
    Hv = np.empty(nv)
    mv = np.empty(nv)
    for i in prange(nv):
        w = anchor[i]
        # the mirror image of the offset across the wall's tangent: d − 2 (d·n̂) n̂
        dn = offset[i, 0] * normal[w, 0] + offset[i, 1] * normal[w, 1]
        d0 = offset[i, 0] - 2.0 * dn * normal[w, 0]
        d1 = offset[i, 1] - 2.0 * dn * normal[w, 1]
        r = _clipped(value[w, 0] + grad[w, 0, 0] * d0 + grad[w, 0, 1] * d1, span[w, 0])
        pv = value[w, 1] + grad[w, 1, 0] * d0 + grad[w, 1, 1] * d1
        vx = _clipped(value[w, 2] + grad[w, 2, 0] * d0 + grad[w, 2, 1] * d1, span[w, 2])
        vy = _clipped(value[w, 3] + grad[w, 3, 0] * d0 + grad[w, 3, 1] * d1, span[w, 3])
        vn = vx * normal[w, 0] + vy * normal[w, 1]
        vel[i, 0] = vx - 2.0 * vn * normal[w, 0]
        vel[i, 1] = vy - 2.0 * vn * normal[w, 1]
        rho[i] = r
        u[i] = _clipped(pv / r, span[w, 1]) / (gamma - 1.0)
        Hv[i] = eta * math.sqrt(volume[i])
        mv[i] = r * volume[i]
    return vel, rho, u, Hv, mv


def virtual_state(wall, x, v, rho, p, m, H, kind, eta, gamma, skew=SKEW):
    """State of the virtual particles from the fluid particles (arguments as
    in :func:`wall_state`; ``eta`` the smoothing factor, ``gamma`` > 1).

    Returns ``(xv, vv, rhov, uv, Hv, mv)``: positions ``(n_v, 2)`` (a copy),
    velocities ``(n_v, 2)``, density, specific internal energy
    ``p_v/((γ−1)ρ_v)``, support ``η √V_v`` and mass ``ρ_v V_v`` (each
    ``(n_v,)``): the Taylor expansion about the anchor wall particle taken
    at the virtual particle's mirror image across the wall's tangent, ρ, p/ρ
    and each velocity component clipped to their range over the fluid in
    front of the anchor (module docstring), the velocity then mirrored about
    the anchor's normal (slip wall).
    """
    eta = positive("eta", eta)
    gamma = positive("gamma", gamma)
    if not gamma > 1.0:
        raise InputError(f"gamma must be > 1; got {gamma:g}.")
    value, grad, span = _state_at_walls(wall, x, v, rho, p, m, H, kind, skew)
    vv, rhov, uv, Hv, mv = _extrapolated(value, grad, span, wall.anchor, wall.offset, wall.normal_wall,
                                         wall.volume, eta, gamma)
    return np.array(wall.x_virtual), vv, rhov, uv, Hv, mv


# --------------------------------------------------------------------------
# safeguard
# --------------------------------------------------------------------------


def _inside(shapes, x, idx):
    """``(particles, phi, shape)`` for the particles of ``idx`` strictly inside
    a shape (one shape each: the one nearest its surface). Candidates are
    sorted by x once, each shape tests only those in its bounding box."""
    bounds = np.array([s.bounds() for s in shapes])
    px, py = x[idx, 0], x[idx, 1]
    near = (px >= bounds[:, 0].min()) & (px <= bounds[:, 2].max())
    near &= (py >= bounds[:, 1].min()) & (py <= bounds[:, 3].max())
    idx = idx[near]
    idx = idx[np.argsort(x[idx, 0], kind="stable")]
    xs = x[idx, 0]
    found, phis, which = [], [], []
    for k, s in enumerate(shapes):
        x0, y0, x1, y1 = bounds[k]
        cand = idx[np.searchsorted(xs, x0, "left"):np.searchsorted(xs, x1, "right")]
        cand = cand[(x[cand, 1] >= y0) & (x[cand, 1] <= y1)]
        phi = s.signed_distance(x[cand, 0], x[cand, 1])
        hit = phi < 0.0
        found.append(cand[hit])
        phis.append(phi[hit])
        which.append(np.full(int(hit.sum()), k))
    j, phi, k = np.concatenate(found), np.concatenate(phis), np.concatenate(which)
    order = np.lexsort((-phi, j))  # per particle, the shallowest shape first
    j, phi, k = j[order], phi[order], k[order]
    first = np.ones(len(j), dtype=bool)
    first[1:] = j[1:] != j[:-1]
    return j[first], phi[first], k[first]


def reflect_into_fluid(shapes, x, *velocities):
    """Put every particle inside an obstacle (``φ < 0``) back at its mirror
    image across the surface, ``x − 2 φ n̂``, and reverse the normal
    component of each of its ``velocities`` that points into the solid
    (``v·n̂ < 0``: ``v − 2 (v·n̂) n̂``).

    ``shapes`` is one :class:`partmesh.cases.shapes.Shape` or a sequence of them,
    ``x`` and every velocity array are ``(n, 2)``. Returns ``(x, *velocities,
    count)``: the inputs themselves when no particle was inside, new arrays
    otherwise (the inputs are never modified), and the number of particles
    moved. A mirror image that lands in another (nearby) obstacle is
    mirrored again; after 4 passes any particle still inside is put just
    outside its closest surface point, so no particle is left inside a solid.
    """
    shapes = [shapes] if isinstance(shapes, Shape) else list(shapes)
    if any(not isinstance(s, Shape) for s in shapes):
        raise InputError("shapes must be a partmesh.cases.shapes.Shape or a sequence of them.")
    x_in = np.asarray(x, dtype=np.float64)
    n = len(x_in)
    if x_in.shape != (n, 2):
        raise InputError(f"x must have shape (n, 2) (obstacles are 2D); got shape {x_in.shape}.")
    v_in = [np.asarray(v, dtype=np.float64) for v in velocities]
    if any(v.shape != (n, 2) for v in v_in):
        raise InputError(f"every velocity must have shape ({n}, 2) like x.")
    if not shapes or n == 0:
        return (x, *velocities, 0)
    x_out, v_out = None, None
    moved = np.zeros(n, dtype=bool)
    todo = np.arange(n)
    for attempt in range(_REFLECT_PASSES + 1):
        j, phi, k = _inside(shapes, x_in if x_out is None else x_out, todo)
        if j.size == 0:
            break
        if x_out is None:
            x_out, v_out = x_in.copy(), [v.copy() for v in v_in]
        moved[j] = True
        for kk in np.unique(k):
            sel = k == kk
            jj, ph = j[sel], phi[sel]
            nx, ny = shapes[kk].normal(x_out[jj, 0], x_out[jj, 1])
            if attempt < _REFLECT_PASSES:
                x_out[jj, 0] -= 2.0 * ph * nx
                x_out[jj, 1] -= 2.0 * ph * ny
            else:  # last resort: just outside the closest surface point
                eps = 1e-9 * shapes[kk].length_scale()
                x_out[jj, 0] += (eps - ph) * nx
                x_out[jj, 1] += (eps - ph) * ny
            for v in v_out:
                vn = v[jj, 0] * nx + v[jj, 1] * ny
                flip = np.where(vn < 0.0, 2.0 * vn, 0.0)
                v[jj, 0] -= flip * nx
                v[jj, 1] -= flip * ny
        todo = j
    if x_out is None:
        return (x, *velocities, 0)
    return (x_out, *v_out, int(moved.sum()))
