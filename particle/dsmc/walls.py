"""Specular reflection of DSMC particles from obstacle polygons (SPEC §3.3).

The obstacles come from the scene's shapes (:mod:`partmesh.cases.shapes`) as closed
counter-clockwise segment loops — a circle as its inscribed polygon with
chords of at most half a cell — so the DSMC body is that polygon. A
particle's straight path over the step is cut at the first segment it
crosses from the fluid side, the velocity is mirrored about the segment's
normal, v ← v − 2(v·n̂)n̂, and the flight goes on for the time left, as many
bounces as it takes. Every shape in the catalogue is convex, which the
safeguard uses: a particle found inside a polygon after the step (a corner
of two walls met in one step, or round-off) is mirrored back across the
nearest face and counted.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.cases.errors import Unsupported
from partmesh.cases.plane_geometry import segment_normals
from partmesh.cases.shapes import Circle
from partmesh.particle.threads import PRANGE_ONLY

#: bounces followed in one step before the safeguard takes over
MAX_BOUNCES = 32


def obstacle_polygons(obstacles, dx):
    """``(segments (M, 2, 2), normals (M, 2), start (G+1,), bbox (G, 4))``:
    the obstacles' boundary loops (obstacle g holds the segments
    ``start[g]:start[g+1]``), their outward unit normals and each obstacle's
    bounding box ``(x0, y0, x1, y1)``. Circles become inscribed polygons with
    chords ≤ dx/2."""
    loops = []
    for shape in obstacles:
        seg = shape.segments(0.5 * dx) if isinstance(shape, Circle) else shape.segments()
        nrm = segment_normals(seg)
        # convex: every vertex lies on the solid side of (or on) every face
        vertices = seg[:, 0, :]
        side = np.einsum("skd,sd->sk", vertices[None, :, :] - seg[:, None, 0, :], nrm)
        if np.any(side > 1e-12 * shape.length_scale()):
            raise Unsupported(f"dsmc reflects from convex obstacles only; {shape.to_dict()['shape']} is not convex.")
        loops.append((seg, nrm))
    if not loops:
        return np.zeros((0, 2, 2)), np.zeros((0, 2)), np.zeros(1, np.int64), np.zeros((0, 4))
    segments = np.concatenate([s for s, _ in loops])
    normals = np.concatenate([n for _, n in loops])
    start = np.concatenate([[0], np.cumsum([len(s) for s, _ in loops])]).astype(np.int64)
    bbox = np.array([[s[:, :, 0].min(), s[:, :, 1].min(), s[:, :, 0].max(), s[:, :, 1].max()] for s, _ in loops])
    return segments, normals, start, bbox


@numba.njit(cache=True, inline="always")
def _crossing(px, py, vx, vy, ax, ay, bx, by, nx, ny, t_max):
    """Time in [0, t_max] at which the path p + v t enters the solid through
    the segment a–b (outward normal n), or +inf."""
    vn = vx * nx + vy * ny
    if vn >= 0.0:
        return math.inf  # moving out of or along the face
    h = (px - ax) * nx + (py - ay) * ny  # height above the face's line, ≥ 0 on the fluid side
    if h < 0.0:
        return math.inf  # behind the face: not on this face's fluid side
    t = -h / vn
    if t > t_max:
        return math.inf
    ex, ey = bx - ax, by - ay
    along = ((px + vx * t - ax) * ex + (py + vy * t - ay) * ey) / (ex * ex + ey * ey)
    if along < 0.0 or along > 1.0:
        return math.inf
    return t


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def fly_past_obstacles(x, v, dt, segments, normals, start, bbox):
    """Move 2D particles ``x`` (n, 2), velocities ``v`` (n, 3), for ``dt``
    in place, reflecting specularly from the obstacle polygons (the domain's
    sides are left to :func:`partmesh.particle.dsmc.move.free_flight`, called after
    with dt = 0). Returns the number of bounces."""
    n = x.shape[0]
    ngroup = start.size - 1
    bounces = np.zeros(n, dtype=np.int64)
    for i in numba.prange(n):
        px, py, vx, vy = x[i, 0], x[i, 1], v[i, 0], v[i, 1]
        left = dt
        last = -1
        for _ in range(MAX_BOUNCES):
            qx, qy = px + vx * left, py + vy * left
            x0, x1 = min(px, qx), max(px, qx)
            y0, y1 = min(py, qy), max(py, qy)
            best = left
            hit = -1
            for g in range(ngroup):
                if x1 < bbox[g, 0] or x0 > bbox[g, 2] or y1 < bbox[g, 1] or y0 > bbox[g, 3]:
                    continue
                for s in range(start[g], start[g + 1]):
                    if s == last:
                        continue
                    t = _crossing(px, py, vx, vy, segments[s, 0, 0], segments[s, 0, 1], segments[s, 1, 0],
                                  segments[s, 1, 1], normals[s, 0], normals[s, 1], best)
                    if t < best or (hit < 0 and t <= best):
                        best = t
                        hit = s
            if hit < 0:
                break
            px += vx * best
            py += vy * best
            vn = vx * normals[hit, 0] + vy * normals[hit, 1]
            vx -= 2.0 * vn * normals[hit, 0]
            vy -= 2.0 * vn * normals[hit, 1]
            left -= best
            last = hit
            bounces[i] += 1
        x[i, 0] = px + vx * left
        x[i, 1] = py + vy * left
        v[i, 0] = vx
        v[i, 1] = vy
    return bounces.sum()


@numba.njit(cache=True, inline="always")
def _face_inside(px, py, segments, normals, s0, s1):
    """``(face, height)``: for a point inside the convex loop of segments
    s0..s1 — below every face's line — its nearest face and the (negative)
    height above it; face −1 outside."""
    nearest = -1
    height = -math.inf
    for s in range(s0, s1):
        h = (px - segments[s, 0, 0]) * normals[s, 0] + (py - segments[s, 0, 1]) * normals[s, 1]
        if h >= 0.0:
            return -1, 0.0
        if h > height:
            height = h
            nearest = s
    return nearest, height


@numba.njit(cache=True, inline="always")
def _obstacle_face_inside(px, py, segments, normals, start, bbox):
    """``(face, height)`` of :func:`_face_inside` for the first obstacle
    whose polygon holds the point strictly inside; face −1 if none. An
    obstacle's faces are looked at only when the point is in its bounding
    box: a point upstream of a circle lies below half its faces' lines,
    so without the box every particle would visit every obstacle's faces."""
    for g in range(start.size - 1):
        if px < bbox[g, 0] or px > bbox[g, 2] or py < bbox[g, 1] or py > bbox[g, 3]:
            continue
        face, height = _face_inside(px, py, segments, normals, start[g], start[g + 1])
        if face >= 0:
            return face, height
    return -1, 0.0


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def inside_obstacles(x, segments, normals, start, bbox):
    """True for the points ``x`` (n, 2) strictly inside an obstacle polygon."""
    n = x.shape[0]
    inside = np.zeros(n, dtype=np.bool_)
    for i in numba.prange(n):
        inside[i] = _obstacle_face_inside(x[i, 0], x[i, 1], segments, normals, start, bbox)[0] >= 0
    return inside


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def push_out_of_obstacles(x, v, segments, normals, start, bbox):
    """The safeguard: a particle inside a (convex) polygon is mirrored back
    across its nearest face and its velocity reflected if it points in.
    Returns the number of particles moved."""
    n = x.shape[0]
    moved = np.zeros(n, dtype=np.int64)
    for i in numba.prange(n):
        face, height = _obstacle_face_inside(x[i, 0], x[i, 1], segments, normals, start, bbox)
        if face >= 0:
            nx, ny = normals[face, 0], normals[face, 1]
            x[i, 0] -= 2.0 * height * nx
            x[i, 1] -= 2.0 * height * ny
            vn = v[i, 0] * nx + v[i, 1] * ny
            if vn < 0.0:
                v[i, 0] -= 2.0 * vn * nx
                v[i, 1] -= 2.0 * vn * ny
            moved[i] = 1
    return moved.sum()


def fluid_fraction(segments, normals, start, bbox, lo, spacing, shape, sub=8):
    """Fraction of each cell of a uniform 2D grid ((ny, nx) array) outside
    the obstacle polygons, from ``sub`` × ``sub`` points per cell (only the cells
    that meet an obstacle's bounding box are sampled)."""
    nx, ny = shape
    fraction = np.ones((ny, nx))
    offsets = (np.arange(sub) + 0.5) / sub
    for g in range(start.size - 1):
        i0, j0 = (np.floor((bbox[g, :2] - lo) / spacing)).astype(int)
        i1, j1 = (np.floor((bbox[g, 2:] - lo) / spacing)).astype(int)
        i0, j0, i1, j1 = max(i0, 0), max(j0, 0), min(i1, nx - 1), min(j1, ny - 1)
        if i1 < i0 or j1 < j0:
            continue
        ci, cj = np.meshgrid(np.arange(i0, i1 + 1), np.arange(j0, j1 + 1))
        px = lo[0] + (ci[..., None, None] + offsets[None, None, None, :]) * spacing[0]
        py = lo[1] + (cj[..., None, None] + offsets[None, None, :, None]) * spacing[1]
        px, py = np.broadcast_arrays(px, py)
        points = np.stack([px.reshape(-1), py.reshape(-1)], axis=1)
        solid = inside_obstacles(points, segments[start[g]:start[g + 1]], normals[start[g]:start[g + 1]],
                                 np.array([0, start[g + 1] - start[g]], dtype=np.int64), bbox[g:g + 1])
        fraction[j0:j1 + 1, i0:i1 + 1] -= solid.reshape(ci.shape + (sub * sub,)).mean(axis=-1)
    return np.clip(fraction, 0.0, 1.0)
