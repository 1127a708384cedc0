"""Plane geometry of points and segments that the obstacle shapes
(:mod:`partmesh.cases.shapes`) are built on: the cross product, the
shoelace area, the distance of points to a segment, the outward normals of
counter-clockwise segments, whether two segments touch, and the checks that
a closed polyline bounds a simple polygon (O'Rourke, "Computational Geometry
in C", 2nd ed., 1998, ch. 1: areas and segment intersection). Vectorised
over arrays of points."""

from __future__ import annotations

import numpy as np


def as_points(x, y) -> tuple[np.ndarray, np.ndarray]:
    """Point coordinates ``x``, ``y`` as float arrays of one broadcast shape."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    return np.broadcast_arrays(x, y)


def cross(ax, ay, bx, by):
    """The z component of the cross product a × b of 2D vectors."""
    return ax * by - ay * bx


def shoelace_area(v: np.ndarray) -> float:
    """Signed area of the polygon with vertices ``v`` (N, 2): positive when they run counter-clockwise
    (the shoelace formula, Σ (x_k y_(k+1) − x_(k+1) y_k) / 2)."""
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def point_segment(px, py, ax, ay, bx, by):
    """Clamped parameter ``t`` and squared distance of points to segment a-b."""
    ex, ey = bx - ax, by - ay
    ll = ex * ex + ey * ey
    t = ((px - ax) * ex + (py - ay) * ey) / ll
    t = np.clip(t, 0.0, 1.0)
    dx = px - (ax + t * ex)
    dy = py - (ay + t * ey)
    return t, dx * dx + dy * dy


def segment_normals(segments: np.ndarray) -> np.ndarray:
    """Outward (solid -> fluid) unit normals ``(M, 2)`` of CCW segments.

    For a segment with direction ``t = p1 - p0`` the normal is the right-hand
    normal ``(t_y, -t_x) / |t|``, because the solid lies to the left of a
    counter-clockwise boundary.
    """
    s = np.asarray(segments, dtype=float)
    t = s[:, 1, :] - s[:, 0, :]
    length = np.hypot(t[:, 0], t[:, 1])
    return np.stack([t[:, 1] / length, -t[:, 0] / length], axis=1)


def segments_touch(a, b, c, d, tol) -> np.ndarray:
    """Closed segments a-b and c-d share a point (broadcast over leading dims;
    last axis holds x, y).  ``tol`` is an absolute length tolerance."""
    rx, ry = b[..., 0] - a[..., 0], b[..., 1] - a[..., 1]
    sx, sy = d[..., 0] - c[..., 0], d[..., 1] - c[..., 1]
    lr = np.hypot(rx, ry)
    ls = np.hypot(sx, sy)
    # signed distances (scaled orientation tests) of each end point to the
    # other segment's line
    o1 = cross(rx, ry, c[..., 0] - a[..., 0], c[..., 1] - a[..., 1]) / lr
    o2 = cross(rx, ry, d[..., 0] - a[..., 0], d[..., 1] - a[..., 1]) / lr
    o3 = cross(sx, sy, a[..., 0] - c[..., 0], a[..., 1] - c[..., 1]) / ls
    o4 = cross(sx, sy, b[..., 0] - c[..., 0], b[..., 1] - c[..., 1]) / ls
    s1, s2, s3, s4 = (np.where(np.abs(o) <= tol, 0, np.sign(o)) for o in (o1, o2, o3, o4))
    proper = (s1 * s2 < 0) & (s3 * s4 < 0)

    def on_seg(p, q, r_, s):
        # point r_ (collinear within tol with p-q) lies within the segment p-q
        qx, qy = q[..., 0] - p[..., 0], q[..., 1] - p[..., 1]
        ll = qx * qx + qy * qy
        t = ((r_[..., 0] - p[..., 0]) * qx + (r_[..., 1] - p[..., 1]) * qy) / ll
        ext = tol / np.sqrt(ll)
        return (s == 0) & (t >= -ext) & (t <= 1 + ext)

    touch = on_seg(a, b, c, s1) | on_seg(a, b, d, s2) | on_seg(c, d, a, s3) | on_seg(c, d, b, s4)
    return proper | touch


def check_no_spike(v: np.ndarray) -> None:
    """Raise ValueError if two adjacent edges fold back onto each other."""
    e = np.roll(v, -1, axis=0) - v
    ep = np.roll(e, 1, axis=0)
    le = np.hypot(e[:, 0], e[:, 1])
    lp = np.hypot(ep[:, 0], ep[:, 1])
    sin = cross(ep[:, 0], ep[:, 1], e[:, 0], e[:, 1]) / (le * lp)
    cos = (ep[:, 0] * e[:, 0] + ep[:, 1] * e[:, 1]) / (le * lp)
    spike = (np.abs(sin) <= 1e-12) & (cos < 0)
    if np.any(spike):
        k = int(np.argmax(spike))
        raise ValueError(
            f"vertices must form a simple polygon, but the edges at vertex {k} fold back onto each other."
        )


def check_no_crossing(v: np.ndarray, tol: float) -> None:
    """Raise ValueError if two non-adjacent edges of the closed polyline meet."""
    n = len(v)
    if n < 4:
        return
    a = v
    b = np.roll(v, -1, axis=0)
    i, j = np.triu_indices(n, k=2)
    keep = ~((i == 0) & (j == n - 1))  # edges 0 and n-1 are adjacent
    i, j = i[keep], j[keep]
    hit = segments_touch(a[i], b[i], a[j], b[j], tol)
    if np.any(hit):
        m = int(np.argmax(hit))
        raise ValueError(
            f"vertices must form a simple (non-self-intersecting) polygon, but edge {i[m]} "
            f"meets edge {j[m]}."
        )
