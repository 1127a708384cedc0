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

The state these particles carry, every step, is in
:mod:`partmesh.particle.sph.wall_state`; the safeguard that no particle ends a step
inside a solid in :mod:`partmesh.particle.sph.wall_reflection`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from partmesh.cases.errors import InputError
from partmesh.cases.shapes import Shape
from partmesh.compare.checks import positive


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
