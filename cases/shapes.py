"""Obstacle geometry: the ONE geometry source for every solver.

The finite-volume immersed boundary (``gridref``), the SPH wall particles and
the DSMC reflecting segments (``particle``) all take their obstacles from the
shapes defined here, so every method sees exactly the same body.

Conventions
-----------
* **Signed distance** ``phi(x, y)``: ``phi < 0`` inside the solid, ``phi > 0``
  in the fluid, ``phi == 0`` on the surface, ``|grad phi| = 1`` (exact
  Euclidean distance to the surface, with a sign).
* **Outward normal** ``n = grad phi``: a unit vector pointing from the solid
  into the fluid.  :meth:`Shape.normal` returns the normal *of the closest
  surface point*, computed analytically (circle: radial direction; polygon:
  from the closest edge, or from the direction to the closest vertex when the
  closest point is a vertex) -- never by finite differences.  For every point
  ``p`` the closest surface point is ``p - phi(p) n(p)``.
* **Segments** (:meth:`Shape.segments`) are an ``(M, 2, 2)`` array
  ``seg[k] = [[x0, y0], [x1, y1]]``, consecutive and closed
  (``seg[k, 1] == seg[k+1, 0]``, ``seg[-1, 1] == seg[0, 0]``) and oriented
  **counter-clockwise** around the solid: walking from the first to the second
  end point, the solid lies on the LEFT and the fluid on the RIGHT.  The
  outward (solid -> fluid) unit normal of a segment with direction
  ``t = (tx, ty)`` is therefore the right-hand normal ``(ty, -tx) / |t|``
  (see :func:`~partmesh.cases.plane_geometry.segment_normals`).  The shoelace area of the segments is
  positive.
* **Polygon** vertices may be given in either orientation; they are stored
  counter-clockwise (positive shoelace area).
* Shapes are frozen dataclasses; ``shape.to_dict()`` gives a JSON-friendly
  ``{"shape": name, ...params}`` and :func:`~partmesh.cases.shape_factories.from_dict` rebuilds the shape
  (``from_dict(s.to_dict()) == s``).

All evaluations are vectorised over arrays of points (numpy broadcasting of
``x`` and ``y``); the only Python loops run over the few edges of a polygon.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from partmesh.cases.plane_geometry import (
    as_points,
    check_no_crossing,
    check_no_spike,
    point_segment,
    shoelace_area,
)
from partmesh.compare.checks import number, positive

__all__ = ["CIRCLE_SEGMENTS", "REL_TOL", "Circle", "Polygon", "Shape"]

#: Number of segments used by ``Circle.segments()`` when no spacing is given.
#: With 128 chords the polygon area is within 4.1e-4 (relative) of pi r^2.
CIRCLE_SEGMENTS = 128

#: relative tolerance (times the length scale of the shapes involved) below
#: which two points, or a point and an edge, are considered to coincide
REL_TOL = 1e-9


# --------------------------------------------------------------------------
# base class
# --------------------------------------------------------------------------
class Shape:
    """A rigid 2D solid described by its exact signed distance.

    Subclasses implement :meth:`signed_distance`, :meth:`normal`,
    :meth:`closest_point`, :meth:`bounds`, :meth:`surface_points`,
    :meth:`segments`, :meth:`area`, :meth:`to_dict` and :meth:`translated`.
    """

    name: str = "shape"

    def signed_distance(self, x, y) -> np.ndarray:  # pragma: no cover - abstract
        """Exact signed distance (< 0 inside, > 0 outside) at broadcast ``x, y``."""
        raise NotImplementedError

    def normal(self, x, y) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
        """Unit outward normal ``(nx, ny)`` of the closest surface point."""
        raise NotImplementedError

    def closest_point(self, x, y) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
        """Closest surface point ``(px, py)`` (equals ``p - phi n``)."""
        raise NotImplementedError

    def bounds(self) -> tuple[float, float, float, float]:  # pragma: no cover
        """Bounding box ``(xmin, ymin, xmax, ymax)``."""
        raise NotImplementedError

    def surface_points(self, spacing: float) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover
        """Points ``(N, 2)`` on the surface, counter-clockwise, at arc-length
        spacing <= ``spacing``, and their outward unit normals ``(N, 2)``."""
        raise NotImplementedError

    def segments(self, spacing: float | None = None) -> np.ndarray:  # pragma: no cover
        """Closed CCW boundary segments ``(M, 2, 2)`` (solid on the left)."""
        raise NotImplementedError

    def area(self) -> float:  # pragma: no cover
        """Exact area of the solid."""
        raise NotImplementedError

    def to_dict(self) -> dict:  # pragma: no cover
        """JSON-friendly ``{"shape": name, ...params}``."""
        raise NotImplementedError

    def translated(self, dx: float, dy: float) -> "Shape":  # pragma: no cover
        """A copy moved by ``(dx, dy)`` (e.g. a periodic image)."""
        raise NotImplementedError

    # ---- shared -----------------------------------------------------------
    def contains(self, x, y) -> np.ndarray:
        """Boolean array, True strictly inside the solid (``phi < 0``)."""
        return np.asarray(self.signed_distance(x, y)) < 0.0

    def frontal_extent(self) -> float:
        """Extent across ``y``: the height seen by a blast travelling in +x."""
        _, ymin, _, ymax = self.bounds()
        return ymax - ymin

    def length_scale(self) -> float:
        """Largest bounding-box side (used to scale geometric tolerances)."""
        xmin, ymin, xmax, ymax = self.bounds()
        return max(xmax - xmin, ymax - ymin)

    @staticmethod
    def _check_spacing(spacing) -> float:
        return positive("spacing", spacing)


# --------------------------------------------------------------------------
# circle
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class Circle(Shape):
    """Solid disc of centre ``(cx, cy)`` and ``radius`` > 0."""

    cx: float
    cy: float
    radius: float

    name = "circle"

    def __post_init__(self):
        object.__setattr__(self, "cx", number("cx", self.cx))
        object.__setattr__(self, "cy", number("cy", self.cy))
        object.__setattr__(self, "radius", positive("radius", self.radius))

    def signed_distance(self, x, y) -> np.ndarray:
        x, y = as_points(x, y)
        return np.hypot(x - self.cx, y - self.cy) - self.radius

    def normal(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Radial unit vector; at the exact centre (undefined) ``(1, 0)``."""
        x, y = as_points(x, y)
        dx, dy = x - self.cx, y - self.cy
        r = np.hypot(dx, dy)
        at_centre = r == 0.0
        rs = np.where(at_centre, 1.0, r)
        nx = np.where(at_centre, 1.0, dx / rs)
        ny = np.where(at_centre, 0.0, dy / rs)
        return nx, ny

    def closest_point(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        nx, ny = self.normal(x, y)
        return self.cx + self.radius * nx, self.cy + self.radius * ny

    def bounds(self) -> tuple[float, float, float, float]:
        r = self.radius
        return (self.cx - r, self.cy - r, self.cx + r, self.cy + r)

    def area(self) -> float:
        return math.pi * self.radius**2

    def _n_points(self, spacing: float) -> int:
        # arc length 2 pi r / N <= spacing; at least a triangle
        return max(3, int(math.ceil(2.0 * math.pi * self.radius / spacing - 1e-12)))

    def surface_points(self, spacing: float) -> tuple[np.ndarray, np.ndarray]:
        """``N = max(3, ceil(2 pi r / spacing))`` points evenly spaced in angle,
        starting at angle 0 (the point ``(cx + r, cy)``), counter-clockwise.

        The arc spacing ``2 pi r / N`` is <= ``spacing`` and >= ``spacing / 2``
        whenever ``spacing <= 2 pi r``.
        """
        spacing = self._check_spacing(spacing)
        n = self._n_points(spacing)
        theta = 2.0 * np.pi * np.arange(n) / n
        c, s = np.cos(theta), np.sin(theta)
        pts = np.stack([self.cx + self.radius * c, self.cy + self.radius * s], axis=1)
        return pts, np.stack([c, s], axis=1)

    def segments(self, spacing: float | None = None) -> np.ndarray:
        """Inscribed regular polygon, counter-clockwise, whose vertices lie ON
        the circle (the points of :meth:`surface_points`): chord length
        ``<= spacing``.  Without ``spacing``, :data:`CIRCLE_SEGMENTS` chords.

        Its area ``(N/2) r^2 sin(2 pi / N)`` undershoots ``pi r^2`` by a
        relative ``<= (2 pi / N)^2 / 6``.
        """
        if spacing is None:
            n = CIRCLE_SEGMENTS
            theta = 2.0 * np.pi * np.arange(n) / n
            pts = np.stack(
                [self.cx + self.radius * np.cos(theta), self.cy + self.radius * np.sin(theta)],
                axis=1,
            )
        else:
            pts, _ = self.surface_points(spacing)
        return np.stack([pts, np.roll(pts, -1, axis=0)], axis=1)

    def to_dict(self) -> dict:
        return {"shape": "circle", "cx": self.cx, "cy": self.cy, "radius": self.radius}

    def translated(self, dx: float, dy: float) -> "Circle":
        return Circle(self.cx + float(dx), self.cy + float(dy), self.radius)


# --------------------------------------------------------------------------
# polygon
# --------------------------------------------------------------------------
@dataclass(frozen=True)
class Polygon(Shape):
    """Solid simple polygon.

    ``vertices`` is a sequence of at least three ``(x, y)`` pairs in either
    orientation (a repeated closing vertex is dropped); it is stored as a
    tuple of float pairs in counter-clockwise order, starting at the first
    vertex given.  Self-intersecting, zero-area or repeated-vertex input
    raises ``ValueError``.

    The signed distance is exact: the minimum distance to the edges, negative
    where the even-odd crossing number says the point is inside.
    """

    vertices: tuple

    name = "polygon"

    def __post_init__(self):
        try:
            v = np.array(self.vertices, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(
                "vertices must be a sequence of (x, y) pairs of finite numbers."
            ) from None
        if v.ndim != 2 or v.shape[1] != 2:
            raise ValueError("vertices must be a sequence of (x, y) pairs of finite numbers.")
        if not np.all(np.isfinite(v)):
            raise ValueError("vertices must be a sequence of (x, y) pairs of finite numbers.")
        if len(v) > 3 and np.array_equal(v[0], v[-1]):
            v = v[:-1]
        if len(v) < 3:
            raise ValueError(f"vertices must hold at least 3 distinct (x, y) points, got {len(v)}.")
        scale = float(np.max(np.ptp(v, axis=0)))
        tol = REL_TOL * max(scale, np.finfo(float).tiny)
        edges = np.roll(v, -1, axis=0) - v
        elen = np.hypot(edges[:, 0], edges[:, 1])
        if scale == 0.0 or np.any(elen <= tol):
            k = int(np.argmin(elen))
            raise ValueError(
                f"vertices must be distinct consecutive points, but vertices {k} and "
                f"{(k + 1) % len(v)} coincide."
            )
        check_no_crossing(v, tol)
        area = shoelace_area(v)
        if abs(area) <= REL_TOL * scale * scale:
            raise ValueError(f"vertices must enclose a positive area, got area {abs(area):.3g}.")
        check_no_spike(v)
        if area < 0:
            v = np.concatenate([v[:1], v[:0:-1]])
        object.__setattr__(self, "vertices", tuple((float(a), float(b)) for a, b in v))

    # ---- cached arrays (cached_property bypasses the frozen __setattr__) --
    @cached_property
    def _v(self) -> np.ndarray:
        a = np.array(self.vertices, dtype=float)
        a.setflags(write=False)
        return a

    @cached_property
    def _edge_normals(self) -> np.ndarray:
        """Outward unit normal of edge k (from vertex k to vertex k+1)."""
        v = self._v
        e = np.roll(v, -1, axis=0) - v
        ll = np.hypot(e[:, 0], e[:, 1])
        n = np.stack([e[:, 1] / ll, -e[:, 0] / ll], axis=1)
        n.setflags(write=False)
        return n

    @cached_property
    def _vertex_normals(self) -> np.ndarray:
        """Unit bisector of the outward normals of the two edges at vertex k."""
        en = self._edge_normals
        s = en + np.roll(en, 1, axis=0)
        ll = np.hypot(s[:, 0], s[:, 1])
        n = s / ll[:, None]
        n.setflags(write=False)
        return n

    # ---- core query ------------------------------------------------------
    def _query(self, x, y):
        """(phi, edge index, clamped t, px, py) of the closest surface point."""
        x, y = as_points(x, y)
        v = self._v
        n = len(v)
        d2 = np.full(x.shape, np.inf)
        best = np.zeros(x.shape, dtype=np.intp)
        tbest = np.zeros(x.shape)
        inside = np.zeros(x.shape, dtype=bool)
        for k in range(n):
            ax, ay = v[k]
            bx, by = v[(k + 1) % n]
            t, dd = point_segment(x, y, ax, ay, bx, by)
            closer = dd < d2
            d2 = np.where(closer, dd, d2)
            best = np.where(closer, k, best)
            tbest = np.where(closer, t, tbest)
            # even-odd crossing number along a ray towards +x
            if ay != by:
                cond = (ay > y) != (by > y)
                xint = ax + (y - ay) * ((bx - ax) / (by - ay))
                inside ^= cond & (x < xint)
        d = np.sqrt(d2)
        phi = np.where(inside, -d, d)
        a = v[best]
        b = v[(best + 1) % n]
        px = a[..., 0] + tbest * (b[..., 0] - a[..., 0])
        py = a[..., 1] + tbest * (b[..., 1] - a[..., 1])
        return phi, best, tbest, px, py, x, y

    def signed_distance(self, x, y) -> np.ndarray:
        x, y = as_points(x, y)
        v = self._v
        n = len(v)
        d2 = np.full(x.shape, np.inf)
        inside = np.zeros(x.shape, dtype=bool)
        for k in range(n):
            ax, ay = v[k]
            bx, by = v[(k + 1) % n]
            np.minimum(d2, point_segment(x, y, ax, ay, bx, by)[1], out=d2)
            if ay != by:
                cond = (ay > y) != (by > y)
                xint = ax + (y - ay) * ((bx - ax) / (by - ay))
                inside ^= cond & (x < xint)
        d = np.sqrt(d2)
        return np.where(inside, -d, d)

    def closest_point(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        _, _, _, px, py, _, _ = self._query(x, y)
        return px, py

    def normal(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Closest point inside an edge: that edge's outward normal.  Closest
        point at a vertex: ``sign(phi) (p - v) / |p - v|`` (the exact gradient),
        or, for a point on the vertex itself, the bisector of the two edge
        normals."""
        phi, k, t, px, py, x, y = self._query(x, y)
        n = len(self._v)
        en = self._edge_normals[k]
        nx, ny = en[..., 0].copy(), en[..., 1].copy()
        at_vertex = (t <= 0.0) | (t >= 1.0)
        if np.any(at_vertex):
            vidx = np.where(t >= 1.0, (k + 1) % n, k)
            d = np.abs(phi)
            eps = 1e-14 * self.length_scale()
            far = at_vertex & (d > eps)
            sgn = np.where(phi < 0, -1.0, 1.0)
            ds = np.where(far, d, 1.0)
            gx = sgn * (x - px) / ds
            gy = sgn * (y - py) / ds
            vn = self._vertex_normals[vidx]
            on = at_vertex & ~far
            nx = np.where(far, gx, np.where(on, vn[..., 0], nx))
            ny = np.where(far, gy, np.where(on, vn[..., 1], ny))
        return nx, ny

    # ---- geometry ----------------------------------------------------------
    def bounds(self) -> tuple[float, float, float, float]:
        v = self._v
        return (float(v[:, 0].min()), float(v[:, 1].min()), float(v[:, 0].max()), float(v[:, 1].max()))

    def area(self) -> float:
        return shoelace_area(self._v)

    def centroid(self) -> tuple[float, float]:
        """Area centroid ``(x, y)``."""
        v = self._v
        x, y = v[:, 0], v[:, 1]
        x1, y1 = np.roll(x, -1), np.roll(y, -1)
        c = x * y1 - x1 * y
        a6 = 6.0 * self.area()
        return float(np.sum((x + x1) * c) / a6), float(np.sum((y + y1) * c) / a6)

    def surface_points(self, spacing: float) -> tuple[np.ndarray, np.ndarray]:
        """Vertices plus evenly spaced points on each edge (edge ``k`` of length
        ``L`` is cut into ``ceil(L / spacing)`` equal pieces), counter-clockwise
        from vertex 0, no duplicates.  Spacing along an edge is <= ``spacing``
        and >= ``spacing / 2`` unless the edge itself is shorter than
        ``spacing / 2``.  Normals: the edge normal between vertices, the
        bisector of the two adjacent edge normals at a vertex."""
        spacing = self._check_spacing(spacing)
        v = self._v
        n = len(v)
        en, vn = self._edge_normals, self._vertex_normals
        pts, nrm = [], []
        for k in range(n):
            a, b = v[k], v[(k + 1) % n]
            length = float(np.hypot(*(b - a)))
            m = max(1, int(math.ceil(length / spacing - 1e-12)))
            t = np.arange(m) / m
            pts.append(a[None, :] + t[:, None] * (b - a)[None, :])
            nk = np.repeat(en[k][None, :], m, axis=0)
            nk[0] = vn[k]
            nrm.append(nk)
        return np.concatenate(pts), np.concatenate(nrm)

    def segments(self, spacing: float | None = None) -> np.ndarray:
        """The polygon's edges, counter-clockwise (solid on the left); with
        ``spacing``, each edge cut into equal pieces <= ``spacing`` (the pieces
        join consecutive :meth:`surface_points`)."""
        if spacing is None:
            pts = np.array(self._v)
        else:
            pts, _ = self.surface_points(spacing)
        return np.stack([pts, np.roll(pts, -1, axis=0)], axis=1)

    def to_dict(self) -> dict:
        return {"shape": "polygon", "vertices": [[a, b] for a, b in self.vertices]}

    def translated(self, dx: float, dy: float) -> "Polygon":
        dx, dy = float(dx), float(dy)
        return Polygon(tuple((a + dx, b + dy) for a, b in self.vertices))
