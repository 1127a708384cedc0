"""Tests for partmesh.cases.shapes, shape_factories and shape_queries: signed distances, normals, surface sampling,
segments, blast-array factories, overlap test and bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.path import Path
from scipy.spatial import cKDTree

from partmesh.cases import shape_factories as F
from partmesh.cases import shape_queries as Q
from partmesh.cases import shapes as S
from partmesh.cases.plane_geometry import segment_normals
from partmesh.cases.shapes import Circle, Polygon

HYP = settings(max_examples=40, deadline=None)

# a non-convex test polygon (an "L" with a notch) and a star, given clockwise
L_SHAPE = ((0.0, 0.0), (0.0, 1.0), (0.4, 1.0), (0.4, 0.3), (1.0, 0.3), (1.0, 0.0))  # CW
STAR = tuple(
    (
        (1.0 if k % 2 == 0 else 0.45) * math.cos(math.pi * k / 5 + 0.1),
        (1.0 if k % 2 == 0 else 0.45) * math.sin(math.pi * k / 5 + 0.1),
    )
    for k in range(10)
)


def all_test_shapes():
    return [
        Circle(0.3, -0.2, 0.7),
        F.square(0.1, 0.2, 0.5),
        F.triangle_left(0.0, 0.0, 0.8),
        F.triangle_right(1.0, 0.5, 0.3),
        F.diamond(-0.5, 0.5, 1.2),
        F.wedge(0.1, 0.0, 20.0, 0.5),
        Polygon(L_SHAPE),
        Polygon(STAR),
    ]


SHAPE_IDS = ["circle", "square", "tri_left", "tri_right", "diamond", "wedge", "L", "star"]


def random_points(shape, n=2000, seed=0, pad=0.5):
    xmin, ymin, xmax, ymax = shape.bounds()
    rng = np.random.default_rng(seed)
    x = rng.uniform(xmin - pad, xmax + pad, n)
    y = rng.uniform(ymin - pad, ymax + pad, n)
    return x, y


def brute_signed_distance(vertices, x, y, delta):
    """Reference: distance to a dense boundary sampling (spacing <= delta),
    sign from matplotlib's point-in-polygon test."""
    v = np.asarray(vertices, float)
    samples = []
    for a, b in zip(v, np.roll(v, -1, axis=0)):
        m = int(math.ceil(np.hypot(*(b - a)) / delta))
        t = np.arange(m) / m
        samples.append(a + t[:, None] * (b - a))
    d, _ = cKDTree(np.concatenate(samples)).query(np.stack([x, y], axis=1))
    inside = Path(v).contains_points(np.stack([x, y], axis=1))
    return np.where(inside, -d, d)


# --------------------------------------------------------------------------
# signed distance against analytic formulas and a brute-force reference
# --------------------------------------------------------------------------
@HYP
@given(
    cx=st.floats(-5, 5),
    cy=st.floats(-5, 5),
    r=st.floats(0.01, 3),
    px=st.floats(-10, 10),
    py=st.floats(-10, 10),
)
def test_circle_signed_distance_analytic(cx, cy, r, px, py):
    c = Circle(cx, cy, r)
    expected = math.sqrt((px - cx) ** 2 + (py - cy) ** 2) - r
    assert float(c.signed_distance(px, py)) == pytest.approx(expected, abs=1e-12)
    assert bool(c.contains(px, py)) == (expected < 0)


def box_sdf(x, y, cx, cy, h):
    qx = np.abs(x - cx) - h
    qy = np.abs(y - cy) - h
    outside = np.hypot(np.maximum(qx, 0), np.maximum(qy, 0))
    return outside + np.minimum(np.maximum(qx, qy), 0.0)


@HYP
@given(cx=st.floats(-3, 3), cy=st.floats(-3, 3), size=st.floats(0.05, 2), seed=st.integers(0, 2**31))
def test_square_signed_distance_analytic(cx, cy, size, seed):
    sq = F.square(cx, cy, size)
    x, y = random_points(sq, n=500, seed=seed, pad=size)
    np.testing.assert_allclose(sq.signed_distance(x, y), box_sdf(x, y, cx, cy, size / 2), atol=1e-12)


def test_circle_signed_distance_vectorised_random():
    c = Circle(1.0, 2.0, 0.5)
    x, y = random_points(c, n=5000, seed=3)
    np.testing.assert_allclose(c.signed_distance(x, y), np.hypot(x - 1, y - 2) - 0.5, atol=1e-14)


@pytest.mark.parametrize("verts", [L_SHAPE, STAR], ids=["L", "star"])
def test_polygon_signed_distance_brute_force(verts):
    poly = Polygon(verts)
    x, y = random_points(poly, n=3000, seed=7, pad=0.4)
    delta = 1e-3
    ref = brute_signed_distance(verts, x, y, delta)
    phi = poly.signed_distance(x, y)
    # sampled distance overestimates the exact one by at most delta/2
    gap = np.abs(ref) - np.abs(phi)
    assert np.all(gap >= -1e-12)
    assert np.all(gap <= delta / 2 + 1e-12)
    # signs agree away from the boundary
    clear = np.abs(phi) > 1e-9
    assert np.all(np.sign(phi[clear]) == np.sign(ref[clear]))
    assert np.any(phi < 0) and np.any(phi > 0)


@HYP
@given(
    n=st.integers(3, 9),
    seed=st.integers(0, 2**31),
)
def test_random_star_polygon_against_brute_force(n, seed):
    # star-shaped (hence simple) random polygon: sorted angles, random radii
    rng = np.random.default_rng(seed)
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    ang = ang + np.arange(n) * 1e-2  # keep angles distinct
    if ang[-1] - ang[0] > 2 * np.pi - 0.05:
        ang = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = rng.uniform(0.3, 1.0, n)
    verts = np.stack([rad * np.cos(ang), rad * np.sin(ang)], axis=1)
    try:
        poly = Polygon(verts)
    except ValueError:  # a near-degenerate draw; nothing to compare
        return
    x, y = random_points(poly, n=400, seed=seed + 1, pad=0.3)
    delta = 2e-3
    ref = brute_signed_distance(verts, x, y, delta)
    phi = poly.signed_distance(x, y)
    gap = np.abs(ref) - np.abs(phi)
    assert np.all((gap >= -1e-12) & (gap <= delta / 2 + 1e-12))
    clear = np.abs(phi) > 1e-9
    assert np.all(np.sign(phi[clear]) == np.sign(ref[clear]))


def test_broadcasting_and_scalars():
    for shp in (Circle(0, 0, 1), F.square(0, 0, 1)):
        x = np.linspace(-2, 2, 7)[:, None]
        y = np.linspace(-2, 2, 5)[None, :]
        phi = shp.signed_distance(x, y)
        assert phi.shape == (7, 5)
        nx, ny = shp.normal(x, y)
        assert nx.shape == ny.shape == (7, 5)
        assert np.ndim(shp.signed_distance(0.0, 0.0)) == 0
    assert float(F.square(0, 0, 1).signed_distance(0.0, 0.0)) == pytest.approx(-0.5)


# --------------------------------------------------------------------------
# normals and closest points
# --------------------------------------------------------------------------
@pytest.mark.parametrize("shp", all_test_shapes(), ids=SHAPE_IDS)
def test_normal_closest_point_consistency(shp):
    x, y = random_points(shp, n=3000, seed=11)
    phi = shp.signed_distance(x, y)
    nx, ny = shp.normal(x, y)
    px, py = shp.closest_point(x, y)
    scale = shp.length_scale()
    np.testing.assert_allclose(np.hypot(nx, ny), 1.0, atol=1e-12)
    np.testing.assert_allclose(shp.signed_distance(px, py), 0.0, atol=1e-12 * scale)
    np.testing.assert_allclose(px, x - phi * nx, atol=1e-12 * scale)
    np.testing.assert_allclose(py, y - phi * ny, atol=1e-12 * scale)
    # |p - closest| = |phi|
    np.testing.assert_allclose(np.hypot(x - px, y - py), np.abs(phi), atol=1e-12 * scale)


@pytest.mark.parametrize("shp", all_test_shapes(), ids=SHAPE_IDS)
def test_normal_is_gradient_of_signed_distance(shp):
    x, y = random_points(shp, n=3000, seed=5)
    h = 1e-6 * shp.length_scale()
    gx = (shp.signed_distance(x + h, y) - shp.signed_distance(x - h, y)) / (2 * h)
    gy = (shp.signed_distance(x, y + h) - shp.signed_distance(x, y - h)) / (2 * h)
    smooth = np.abs(np.hypot(gx, gy) - 1.0) < 1e-7  # not straddling a kink
    assert smooth.mean() > 0.95
    nx, ny = shp.normal(x, y)
    np.testing.assert_allclose(nx[smooth], gx[smooth], atol=1e-3)
    np.testing.assert_allclose(ny[smooth], gy[smooth], atol=1e-3)


def test_normals_point_outward_specific_values():
    sq = F.square(0, 0, 2)
    nx, ny = sq.normal(np.array([3.0, 0.0, 0.5, 2.0]), np.array([0.0, -3.0, 0.0, 2.0]))
    np.testing.assert_allclose(nx, [1, 0, 1, math.sqrt(0.5)], atol=1e-15)
    np.testing.assert_allclose(ny, [0, -1, 0, math.sqrt(0.5)], atol=1e-15)
    # on a vertex: bisector of the two edge normals
    nx, ny = sq.normal(1.0, 1.0)
    assert (float(nx), float(ny)) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))
    # reflex vertex of the L from inside: normal points from p toward the vertex
    poly = Polygon(L_SHAPE)
    nx, ny = poly.normal(0.35, 0.25)
    d = math.hypot(0.05, 0.05)
    assert float(poly.signed_distance(0.35, 0.25)) == pytest.approx(-d)
    assert (float(nx), float(ny)) == pytest.approx((0.05 / d, 0.05 / d))
    # circle centre: a defined unit vector
    c = Circle(1, 1, 1)
    nx, ny = c.normal(1.0, 1.0)
    assert math.hypot(float(nx), float(ny)) == pytest.approx(1.0)


# --------------------------------------------------------------------------
# surface points and segments
# --------------------------------------------------------------------------
@pytest.mark.parametrize("shp", all_test_shapes(), ids=SHAPE_IDS)
@pytest.mark.parametrize("spacing", [0.013, 0.05])
def test_surface_points(shp, spacing):
    pts, nrm = shp.surface_points(spacing)
    assert pts.ndim == 2 and pts.shape[1] == 2 and nrm.shape == pts.shape
    np.testing.assert_array_less(np.abs(shp.signed_distance(pts[:, 0], pts[:, 1])), 1e-12)
    np.testing.assert_allclose(np.hypot(nrm[:, 0], nrm[:, 1]), 1.0, atol=1e-12)
    # normals agree with Shape.normal at the same points
    nx, ny = shp.normal(pts[:, 0], pts[:, 1])
    np.testing.assert_allclose(np.stack([nx, ny], axis=1), nrm, atol=1e-9)
    step = np.hypot(*(np.roll(pts, -1, axis=0) - pts).T)
    if isinstance(shp, Circle):
        arc = 2 * shp.radius * np.arcsin(np.clip(step / (2 * shp.radius), 0, 1))
        assert np.all(arc <= spacing * (1 + 1e-12))
    assert np.all(step <= spacing * (1 + 1e-12))
    assert np.all(step >= 0.5 * spacing)
    # no duplicates anywhere
    d, _ = cKDTree(pts).query(pts, k=2)
    assert np.all(d[:, 1] > 1e-9)
    # the arc length adds up to the perimeter (polygons exactly)
    if isinstance(shp, Polygon):
        v = np.asarray(shp.vertices)
        perim = np.sum(np.hypot(*(np.roll(v, -1, axis=0) - v).T))
        assert step.sum() == pytest.approx(perim, rel=1e-12)
        # every vertex is one of the points
        dv, _ = cKDTree(pts).query(v)
        assert np.all(dv < 1e-14)


def test_surface_points_even_along_edges():
    sq = F.square(0, 0, 1)
    pts, _ = sq.surface_points(0.3)  # each side in 4 pieces of 0.25
    assert len(pts) == 16
    step = np.hypot(*(np.roll(pts, -1, axis=0) - pts).T)
    np.testing.assert_allclose(step, 0.25, atol=1e-15)
    c = Circle(0, 0, 1)
    pts, nrm = c.surface_points(0.1)
    assert len(pts) == math.ceil(2 * math.pi / 0.1)
    np.testing.assert_allclose(nrm, pts, atol=1e-15)  # unit circle: normal == position


def shoelace(pts):
    x, y = pts[:, 0], pts[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


@pytest.mark.parametrize("shp", all_test_shapes(), ids=SHAPE_IDS)
@pytest.mark.parametrize("spacing", [None, 0.02])
def test_segments_closed_ccw(shp, spacing):
    seg = shp.segments(spacing)
    assert seg.ndim == 3 and seg.shape[1:] == (2, 2)
    # closed chain
    np.testing.assert_array_equal(seg[:-1, 1], seg[1:, 0])
    np.testing.assert_array_equal(seg[-1, 1], seg[0, 0])
    length = np.hypot(*(seg[:, 1] - seg[:, 0]).T)
    assert np.all(length > 0)
    if spacing is not None:
        assert np.all(length <= spacing * (1 + 1e-12))
    area = shoelace(seg[:, 0])
    assert area > 0  # counter-clockwise
    if isinstance(shp, Polygon):
        assert area == pytest.approx(shp.area(), rel=1e-12)
    else:
        r = shp.radius
        m = len(seg)
        assert area == pytest.approx(0.5 * m * r * r * math.sin(2 * math.pi / m), rel=1e-12)
        assert area < shp.area()
        assert (shp.area() - area) / shp.area() <= (2 * math.pi / m) ** 2 / 6
        # vertices on the circle
        np.testing.assert_allclose(shp.signed_distance(seg[:, 0, 0], seg[:, 0, 1]), 0.0, atol=1e-12)
    # the documented normal relation: right-hand normal points into the fluid
    n = segment_normals(seg)
    mid = seg.mean(axis=1)
    if isinstance(shp, Polygon):
        eps = 1e-6 * shp.length_scale()
        assert np.all(shp.signed_distance(mid[:, 0] + eps * n[:, 0], mid[:, 1] + eps * n[:, 1]) > 0)
        assert np.all(shp.signed_distance(mid[:, 0] - eps * n[:, 0], mid[:, 1] - eps * n[:, 1]) < 0)
    else:  # a chord's outward normal is the radial direction at its midpoint
        nx, ny = shp.normal(mid[:, 0], mid[:, 1])
        np.testing.assert_allclose(n, np.stack([nx, ny], axis=1), atol=1e-12)


def test_circle_segments_default_count():
    seg = Circle(0, 0, 2).segments()
    assert len(seg) == S.CIRCLE_SEGMENTS


def test_polygon_stored_ccw_from_either_orientation():
    cw = Polygon(L_SHAPE)
    ccw = Polygon(tuple(reversed(L_SHAPE)))
    assert shoelace(np.asarray(cw.vertices)) > 0
    assert cw.vertices[0] == L_SHAPE[0]
    assert cw.area() == pytest.approx(0.4 * 1.0 + 0.6 * 0.3)
    assert set(cw.vertices) == set(ccw.vertices)
    x, y = random_points(cw, n=500, seed=2)
    np.testing.assert_allclose(cw.signed_distance(x, y), ccw.signed_distance(x, y), atol=1e-15)
    # a repeated closing vertex is dropped
    closed = Polygon(L_SHAPE + (L_SHAPE[0],))
    assert closed == cw


# --------------------------------------------------------------------------
# blast-array factories
# --------------------------------------------------------------------------
@pytest.mark.parametrize("name", sorted(F.SHAPES))
def test_blast_shapes_equal_frontal_extent(name):
    zeta = 0.0267
    shp = F.SHAPES[name](0.3, 0.06, zeta)
    assert shp.frontal_extent() == pytest.approx(zeta, rel=1e-14)
    expected_area = {
        "circle": math.pi * zeta**2 / 4,
        "square": zeta**2,
        "triangle_left": math.sqrt(3) / 4 * zeta**2,
        "triangle_right": math.sqrt(3) / 4 * zeta**2,
        "diamond": zeta**2 / 2,
    }[name]
    assert shp.area() == pytest.approx(expected_area, rel=1e-12)
    xmin, ymin, xmax, ymax = shp.bounds()
    assert 0.5 * (ymin + ymax) == pytest.approx(0.06, abs=1e-15)
    assert bool(shp.contains(0.3, 0.06))
    if isinstance(shp, Polygon):
        assert shp.centroid() == pytest.approx((0.3, 0.06), abs=1e-14)
    assert F.from_dict(shp.to_dict()) == shp


def test_triangle_orientation():
    zeta = 1.0
    h = math.sqrt(3) / 2
    left = F.triangle_left(0.0, 0.0, zeta)
    v = np.asarray(left.vertices)
    i = int(np.argmin(v[:, 0]))
    assert np.sum(v[:, 0] == v[i, 0]) == 1  # a unique apex upstream
    assert v[i, 1] == pytest.approx(0.0)
    base = v[np.arange(3) != i]
    assert base[0, 0] == base[1, 0]  # flat vertical base downstream
    assert abs(base[0, 1] - base[1, 1]) == pytest.approx(zeta)
    assert base[0, 0] - v[i, 0] == pytest.approx(h)
    assert v[i, 0] == pytest.approx(-2 * h / 3)  # centroid anchor

    right = F.triangle_right(0.0, 0.0, zeta)
    w = np.asarray(right.vertices)
    j = int(np.argmax(w[:, 0]))
    assert np.sum(w[:, 0] == w[j, 0]) == 1  # apex downstream
    base = w[np.arange(3) != j]
    assert base[0, 0] == base[1, 0] == pytest.approx(-h / 3)  # base faces the blast
    # mirror images of each other about x = cx
    assert set(map(tuple, np.round(w * [-1, 1], 14))) == set(map(tuple, np.round(v, 14)))

    bb = F.triangle_left(0.0, 0.0, zeta, anchor="bbox")
    xmin, _, xmax, _ = bb.bounds()
    assert 0.5 * (xmin + xmax) == pytest.approx(0.0, abs=1e-15)


def test_diamond_and_square_geometry():
    d = F.diamond(0, 0, 2)
    assert set(d.vertices) == {(-1.0, 0.0), (0.0, -1.0), (1.0, 0.0), (0.0, 1.0)}
    assert float(d.signed_distance(1.0, 1.0)) == pytest.approx(math.sqrt(0.5))
    s = F.square(1, 1, 2)
    assert s.bounds() == (0.0, 0.0, 2.0, 2.0)


def test_wedge():
    w = F.wedge(0.2, 0.0, 30.0, 1.0)
    v = np.asarray(w.vertices)
    np.testing.assert_allclose(v, [[0.2, 0], [1.2, 0], [1.2, math.tan(math.radians(30))]])
    assert w.frontal_extent() == pytest.approx(math.tan(math.radians(30)))
    # the upper face makes the half angle with the wall
    nx, ny = w.normal(0.7, 1.0)
    assert math.degrees(math.atan2(float(nx), float(ny))) == pytest.approx(-30.0)
    assert F.from_dict({"shape": "wedge", "x_apex": 0.2, "y_wall": 0.0, "half_angle_deg": 30.0, "length": 1.0}) == w


# --------------------------------------------------------------------------
# dict round trips, collections, translation
# --------------------------------------------------------------------------
@pytest.mark.parametrize("shp", all_test_shapes(), ids=SHAPE_IDS)
def test_dict_round_trip_through_json(shp):
    d = json.loads(json.dumps(shp.to_dict()))
    assert d["shape"] in ("circle", "polygon")
    back = F.from_dict(d)
    assert back == shp and type(back) is type(shp)
    assert hash(back) == hash(shp)


def test_from_dict_factory_forms():
    assert F.from_dict({"shape": "square", "cx": 0, "cy": 0, "size": 1}) == F.square(0, 0, 1)
    assert F.from_dict({"shape": "circle", "cx": 0, "cy": 0, "size": 1}) == Circle(0, 0, 0.5)
    assert F.from_dict({"shape": "triangle_left", "cx": 0, "cy": 0, "size": 1, "anchor": "bbox"}) == (
        F.triangle_left(0, 0, 1, anchor="bbox")
    )


def test_collection_union():
    shapes = [Circle(0, 0, 1), F.square(3, 0, 1)]
    x = np.array([0.0, 3.0, 1.5, 10.0])
    y = np.zeros(4)
    phi = Q.signed_distance(shapes, x, y)
    np.testing.assert_allclose(phi, [-1.0, -0.5, 0.5, 6.5])
    np.testing.assert_array_equal(Q.solid_mask(shapes, x, y), [True, True, False, False])
    _, idx = Q.nearest(shapes, x, y)
    np.testing.assert_array_equal(idx, [0, 1, 0, 1])
    nx, ny = Q.normal(shapes, x[2:], y[2:])
    np.testing.assert_allclose(nx, [1.0, 1.0])
    empty = Q.signed_distance([], np.zeros((2, 3)), 0.0)
    assert empty.shape == (2, 3) and np.all(np.isinf(empty)) and np.all(empty > 0)
    assert not np.any(Q.solid_mask([], x, y))
    # a single shape is accepted too
    np.testing.assert_allclose(Q.signed_distance(shapes[0], x, y), shapes[0].signed_distance(x, y))


def test_translated():
    for shp in all_test_shapes():
        moved = shp.translated(0.5, -0.04)
        x, y = random_points(shp, n=200, seed=9)
        np.testing.assert_allclose(
            moved.signed_distance(x + 0.5, y - 0.04), shp.signed_distance(x, y), atol=1e-13
        )


# --------------------------------------------------------------------------
# overlaps
# --------------------------------------------------------------------------
def both(a, b, clearance=0.0):
    r1 = Q.overlaps(a, b, clearance)
    r2 = Q.overlaps(b, a, clearance)
    assert r1 == r2
    return r1


def test_overlaps_circles():
    a = Circle(0, 0, 1)
    assert not both(a, Circle(3, 0, 1))  # disjoint, gap 1
    assert not both(a, Circle(2, 0, 1))  # touching
    assert both(a, Circle(2, 0, 1), clearance=1e-6)
    assert both(a, Circle(1.5, 0, 1))  # overlapping
    assert both(a, Circle(0.1, 0, 0.2))  # contained
    assert both(a, Circle(3, 0, 1), clearance=1.01)
    assert not both(a, Circle(3, 0, 1), clearance=0.99)


def test_overlaps_circle_polygon():
    c = Circle(0, 0, 0.5)
    assert not both(c, F.square(1.0, 0, 1))  # touching at (0.5, 0)
    assert both(c, F.square(0.99, 0, 1))
    assert not both(c, F.square(2.0, 0, 1))
    assert both(c, F.square(2.0, 0, 1), clearance=1.01)
    assert not both(c, F.square(2.0, 0, 1), clearance=0.99)
    assert both(c, F.square(0, 0, 0.1))  # polygon inside the circle
    assert both(Circle(0, 0, 0.01), F.square(0, 0, 1))  # circle inside the polygon
    # near a corner: the gap is measured to the vertex, not the edge lines
    sq = F.square(1.0, 1.0, 1.0)  # corner at (0.5, 0.5)
    gap = math.hypot(0.5, 0.5) - 0.5
    assert not both(c, sq)
    assert both(c, sq, clearance=gap * 1.001)
    assert not both(c, sq, clearance=gap * 0.999)


def test_overlaps_polygons():
    a = F.square(0, 0, 1)
    assert not both(a, F.square(1.0, 0, 1))  # sharing an edge: touching
    assert not both(a, F.square(1.0, 1.0, 1))  # sharing a corner
    assert not both(a, F.square(1.0, 0.3, 1))  # sharing part of an edge
    assert not both(a, F.diamond(1.0, 0.0, 1.0))  # diamond vertex on a's edge
    assert both(a, F.square(0.5, 0, 1))  # half-shifted copy: boundaries meet only on a's edges
    assert both(a, F.square(0, 0, 1))  # identical
    assert both(a, F.square(0.1, 0.1, 0.2))  # contained
    assert both(a, F.square(0.99, 0, 1))
    # gap 0.5 side by side
    b = F.square(1.5, 0, 1)
    assert not both(a, b)
    assert both(a, b, clearance=0.51)
    assert not both(a, b, clearance=0.49)
    # star of David: no vertex of either triangle inside the other, edges cross
    t1 = Polygon(((0, 1), (-math.sqrt(3) / 2, -0.5), (math.sqrt(3) / 2, -0.5)))
    t2 = Polygon(((0, -1), (math.sqrt(3) / 2, 0.5), (-math.sqrt(3) / 2, 0.5)))
    assert np.all(t2.signed_distance(*np.asarray(t1.vertices).T) > 0)
    assert both(t1, t2)
    # a cross of two thin rectangles: all vertices outside the other one
    h = Polygon(((-2, -0.1), (2, -0.1), (2, 0.1), (-2, 0.1)))
    v = Polygon(((-0.1, -2), (0.1, -2), (0.1, 2), (-0.1, 2)))
    assert both(h, v)
    # a triangle nested in the notch of the L, touching both faces
    L = Polygon(L_SHAPE)
    assert not both(L, F.square(0.7, 0.65, 0.6))  # [0.4,1]x[0.35,0.95]: gap 0.05 to the L
    assert both(L, F.square(0.7, 0.65, 0.6), clearance=0.06)
    assert not both(L, Polygon(((0.4, 0.3), (1.0, 0.3), (0.4, 0.9))))  # sits in the notch, touching


def test_overlaps_gap_sweep_matches_distance():
    # a diamond slid toward a triangle: the overlap switch sits at the exact gap
    tri = F.triangle_right(0.0, 0.0, 1.0)  # apex at x = 2h/3
    apex = 2 * (math.sqrt(3) / 2) / 3
    for gap in (0.3, 0.05, 1e-3):
        dia = F.diamond(apex + gap + 0.5, 0.0, 1.0)
        assert not both(tri, dia, clearance=gap * (1 - 1e-6))
        assert both(tri, dia, clearance=gap * (1 + 1e-6))
    assert not both(tri, F.diamond(apex + 0.5, 0.0, 1.0))  # vertex to vertex
    assert both(tri, F.diamond(apex + 0.49, 0.0, 1.0))


# --------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------
def one_sentence(msg: str, name: str):
    assert name in msg
    assert "\n" not in msg and msg.endswith(".")


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: Circle(0, 0, 0), "radius"),
        (lambda: Circle(0, 0, -1), "radius"),
        (lambda: Circle(0, 0, float("nan")), "radius"),
        (lambda: Circle(float("inf"), 0, 1), "cx"),
        (lambda: F.circle(0, 0, 0), "size"),
        (lambda: F.square(0, 0, -0.1), "size"),
        (lambda: F.triangle_left(0, 0, 0), "size"),
        (lambda: F.triangle_right(0, 0, float("inf")), "size"),
        (lambda: F.diamond(0, 0, "big"), "size"),
        (lambda: F.triangle_left(0, 0, 1, anchor="middle"), "anchor"),
        (lambda: F.wedge(0, 0, 0, 1), "half_angle_deg"),
        (lambda: F.wedge(0, 0, 90, 1), "half_angle_deg"),
        (lambda: F.wedge(0, 0, 20, 0), "length"),
        (lambda: Polygon(((0, 0), (1, 0))), "vertices"),
        (lambda: Polygon(((0, 0), (1, 0), (1, 1), (0, 1), (0, 0), (0, 0))), "vertices"),
        (lambda: Polygon(((0, 0), (1, 1), (1, 0), (0, 1))), "vertices"),  # bow tie
        (lambda: Polygon(((0, 0), (1, 0), (2, 0))), "vertices"),  # zero area
        (lambda: Polygon(((0, 0), (1, 0), (1, 0), (0, 1))), "vertices"),  # repeated vertex
        (lambda: Polygon(((0, 0), (2, 0), (1, 0), (1, 1), (0, 1))), "vertices"),  # spike
        (lambda: Polygon(((0, 0), (2, 0), (2, 2), (1, 0.0), (0, 2))), "vertices"),  # vertex on edge
        (lambda: Polygon(((0, 0), (1, float("nan")), (1, 1))), "vertices"),
        (lambda: Polygon("abc"), "vertices"),
        (lambda: F.square(0, 0, 1).surface_points(0), "spacing"),
        (lambda: Circle(0, 0, 1).segments(-1), "spacing"),
        (lambda: Q.overlaps(Circle(0, 0, 1), Circle(3, 0, 1), -1), "clearance"),
        (lambda: F.from_dict({"shape": "hexagon"}), "shape"),
        (lambda: F.from_dict({"cx": 1}), "shape"),
        (lambda: F.from_dict({"shape": "square", "cx": 0}), "square"),
    ],
)
def test_bad_input(call, name):
    with pytest.raises(ValueError) as err:
        call()
    one_sentence(str(err.value), name)


def test_bad_input_messages_are_specific():
    with pytest.raises(ValueError, match="radius must be a finite number > 0, got -1"):
        Circle(0, 0, -1)
    with pytest.raises(ValueError, match="at least 3"):
        Polygon(((0, 0), (1, 0)))
    with pytest.raises(ValueError, match="simple"):
        Polygon(((0, 0), (1, 1), (1, 0), (0, 1)))
    with pytest.raises(ValueError, match="positive area"):
        Polygon(((0, 0), (1, 0), (2, 0)))
    with pytest.raises(ValueError, match=r"\(0, 90\)"):
        F.wedge(0, 0, 95, 1)
