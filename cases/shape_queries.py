"""Queries over several obstacle shapes at once: the signed distance to the
nearest body, the solid mask, the nearest surface point and its normal,
and whether two bodies overlap (the scene checks refuse that)."""

from __future__ import annotations

import math
from typing import Iterable

import numpy as np

from partmesh.cases.plane_geometry import as_points, cross
from partmesh.cases.shapes import REL_TOL, Circle, Polygon, Shape


def _as_list(shapes) -> list[Shape]:
    if isinstance(shapes, Shape):
        return [shapes]
    return list(shapes)


def signed_distance(shapes: Iterable[Shape] | Shape, x, y) -> np.ndarray:
    """Signed distance of the union of ``shapes``: the minimum over shapes
    (exact outside the solids; inside it is exact for non-overlapping
    shapes).  ``+inf`` everywhere for an empty collection."""
    x, y = as_points(x, y)
    out = np.full(x.shape, np.inf)
    for s in _as_list(shapes):
        out = np.minimum(out, s.signed_distance(x, y))
    return out


def solid_mask(shapes: Iterable[Shape] | Shape, x, y) -> np.ndarray:
    """True where a point lies strictly inside any of ``shapes``."""
    return signed_distance(shapes, x, y) < 0.0


def nearest(shapes: Iterable[Shape] | Shape, x, y) -> tuple[np.ndarray, np.ndarray]:
    """``(phi, index)``: union signed distance and the index of the shape
    that attains it (-1 where the collection is empty)."""
    x, y = as_points(x, y)
    phi = np.full(x.shape, np.inf)
    idx = np.full(x.shape, -1, dtype=np.intp)
    for k, s in enumerate(_as_list(shapes)):
        p = s.signed_distance(x, y)
        closer = p < phi
        phi = np.where(closer, p, phi)
        idx = np.where(closer, k, idx)
    return phi, idx


def normal(shapes: Iterable[Shape] | Shape, x, y) -> tuple[np.ndarray, np.ndarray]:
    """Outward unit normal of the nearest shape's closest surface point
    (NaN where the collection is empty)."""
    x, y = as_points(x, y)
    shapes = _as_list(shapes)
    _, idx = nearest(shapes, x, y)
    nx = np.full(x.shape, np.nan)
    ny = np.full(x.shape, np.nan)
    for k, s in enumerate(shapes):
        sel = idx == k
        if np.any(sel):
            a, b = s.normal(x[sel], y[sel])
            nx[sel], ny[sel] = a, b
    return nx, ny


# --------------------------------------------------------------------------
# overlap test
# --------------------------------------------------------------------------
def _polygon_interiors_meet(a: Polygon, b: Polygon, tol: float) -> bool:
    """Exact test whether the open interiors of two simple polygons intersect.

    Each edge of ``a`` is split at every point where it meets the boundary of
    ``b`` (edge crossings and ``b``'s vertices on it); the midpoint of each
    piece is then either strictly inside ``b`` (interiors meet), strictly
    outside, or on ``b``'s boundary (a shared stretch of edge: the interiors
    meet iff both outward normals point the same way).  Done both ways round,
    this is complete: the boundary of ``int a & int b`` is made of such pieces.
    """
    va, vb = a._v, b._v
    na = len(va)
    b0 = vb
    b1 = np.roll(vb, -1, axis=0)
    sx, sy = b1[:, 0] - b0[:, 0], b1[:, 1] - b0[:, 1]
    mids, outn = [], []
    for k in range(na):
        p, q = va[k], va[(k + 1) % na]
        rx, ry = q - p
        ll = rx * rx + ry * ry
        ts = [np.array([0.0, 1.0])]
        # crossings with non-parallel edges of b
        den = cross(rx, ry, sx, sy)
        ok = np.abs(den) > 1e-14 * math.sqrt(ll) * np.hypot(sx, sy)
        dsafe = np.where(ok, den, 1.0)
        cx_, cy_ = b0[:, 0] - p[0], b0[:, 1] - p[1]
        t = cross(cx_, cy_, sx, sy) / dsafe
        u = cross(cx_, cy_, rx, ry) / dsafe
        good = ok & (t > 0) & (t < 1) & (u >= -1e-12) & (u <= 1 + 1e-12)
        ts.append(t[good])
        # b's vertices lying on this edge
        tv = ((vb[:, 0] - p[0]) * rx + (vb[:, 1] - p[1]) * ry) / ll
        dist = np.abs(cross(rx, ry, vb[:, 0] - p[0], vb[:, 1] - p[1])) / math.sqrt(ll)
        ts.append(tv[(dist <= tol) & (tv > 0) & (tv < 1)])
        tt = np.unique(np.concatenate(ts))
        tm = 0.5 * (tt[:-1] + tt[1:])[np.diff(tt) * math.sqrt(ll) > tol]
        mids.append(p[None, :] + tm[:, None] * (q - p)[None, :])
        outn.append(np.repeat(a._edge_normals[k][None, :], len(tm), axis=0))
    m = np.concatenate(mids)
    en = np.concatenate(outn)
    phi = b.signed_distance(m[:, 0], m[:, 1])
    if np.any(phi < -tol):
        return True
    on = np.abs(phi) <= tol
    if np.any(on):
        nx, ny = b.normal(m[on, 0], m[on, 1])
        if np.any(nx * en[on, 0] + ny * en[on, 1] > 0.5):
            return True
    return False


def overlaps(a: Shape, b: Shape, clearance: float = 0.0) -> bool:
    """Whether the solids ``a`` and ``b`` come closer than ``clearance``.

    True if their interiors intersect, or if the gap between them is smaller
    than ``clearance`` (within a relative tolerance of 1e-9 of the shapes'
    size).  Shapes that merely touch do NOT overlap at ``clearance = 0``.
    The test is exact (no sampling): circle/circle compares the centre
    distance with the radii; circle/polygon compares the polygon's signed
    distance at the centre with the radius; polygon/polygon tests the
    interiors exactly (edges split at all mutual contacts, see
    ``_polygon_interiors_meet``) and takes the gap as the smallest
    vertex-to-boundary distance, which is exact for disjoint polygons.
    """
    clearance = float(clearance)
    if not (math.isfinite(clearance) and clearance >= 0.0):
        raise ValueError(f"clearance must be a finite number >= 0, got {clearance!r}.")
    tol = REL_TOL * max(a.length_scale(), b.length_scale())
    if isinstance(a, Circle) and isinstance(b, Circle):
        gap = math.hypot(a.cx - b.cx, a.cy - b.cy) - a.radius - b.radius
        return gap < clearance - tol
    if isinstance(a, Circle) and isinstance(b, Polygon):
        a, b = b, a
    if isinstance(a, Polygon) and isinstance(b, Circle):
        gap = float(a.signed_distance(b.cx, b.cy)) - b.radius
        return gap < clearance - tol
    if isinstance(a, Polygon) and isinstance(b, Polygon):
        if _polygon_interiors_meet(a, b, tol) or _polygon_interiors_meet(b, a, tol):
            return True
        if clearance == 0.0:
            return False
        gap = min(
            float(np.min(np.abs(b.signed_distance(a._v[:, 0], a._v[:, 1])))),
            float(np.min(np.abs(a.signed_distance(b._v[:, 0], b._v[:, 1])))),
        )
        return gap < clearance - tol
    raise ValueError(
        f"a and b must be Circle or Polygon shapes, got {type(a).__name__} and {type(b).__name__}."
    )
