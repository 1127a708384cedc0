"""Particle → output-grid deposition (partmesh.compare.deposit): Shepard interpolation
for SPH, cell sums and ideal-gas moments for DSMC."""

from __future__ import annotations

import numpy as np
import pytest

from partmesh.cases.errors import InputError
from partmesh.compare.deposit import cell_average, moments_to_primitive, shepard

# --- kernels written here (the solver passes its own) -----------------------


def wendland_c2_2d(r, H):
    """Wendland C2 in 2D, compact support H: W = 7/(πH²)(1−q)^4(1+4q), q = r/H."""
    q = np.asarray(r) / H
    return np.where(q < 1, 7.0 / (np.pi * H**2) * np.clip(1 - q, 0, None) ** 4 * (1 + 4 * q), 0.0)


def wendland_c2_1d(r, H):
    """Wendland C2 in 1D, compact support H: W = 5/(4H)(1−q)^3(1+3q), q = r/H."""
    q = np.asarray(r) / H
    return np.where(q < 1, 5.0 / (4.0 * H) * np.clip(1 - q, 0, None) ** 3 * (1 + 3 * q), 0.0)


def test_test_kernels_are_normalised():
    H = 0.7
    r = np.linspace(0, H, 200001)
    w1 = wendland_c2_1d(r, H)
    w2 = wendland_c2_2d(r, H)
    assert np.trapezoid(2 * w1, r) == pytest.approx(1.0, rel=1e-8)
    assert np.trapezoid(2 * np.pi * r * w2, r) == pytest.approx(1.0, rel=1e-8)


def centres(x0, x1, n):
    """Cell centres of n uniform cells on [x0, x1]."""
    h = (x1 - x0) / n
    return x0 + h * (np.arange(n) + 0.5)


def dense_shepard(points, values, volumes, support, grid_x, grid_y, kernel, min_support=1e-3):
    """Brute-force reference: every grid point against every particle."""
    if grid_y is None:
        g = grid_x[:, None]
        shape = (grid_x.size,)
    else:
        Y, X = np.meshgrid(grid_y, grid_x, indexing="ij")
        g = np.column_stack([X.ravel(), Y.ravel()])
        shape = (grid_y.size, grid_x.size)
    pts = points.reshape(len(points), -1)
    r = np.sqrt(((g[:, None, :] - pts[None, :, :]) ** 2).sum(axis=-1))
    H = np.broadcast_to(support, r.shape)
    w = np.where(r < H, kernel(r, H), 0.0) * volumes
    den = w.sum(axis=1)
    num = np.atleast_2d(values) @ w.T
    out = np.where((den > 0) & (den >= min_support), num / np.where(den > 0, den, 1), np.nan)
    out = out.reshape((-1,) + shape)
    return out[0] if np.ndim(values) == 1 else out


def lattice_2d(n, L=1.0):
    """Uniform square lattice of n × n particles on [0, L]², spacing dx."""
    dx = L / n
    c = centres(0.0, L, n)
    Y, X = np.meshgrid(c, c, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel()]), dx


# --- Shepard: exactness -------------------------------------------------------


def test_constant_reproduced_2d_jittered_particles_variable_h():
    rng = np.random.default_rng(1)
    pts, dx = lattice_2d(30)
    pts = pts + rng.uniform(-0.3, 0.3, pts.shape) * dx
    n = len(pts)
    vol = dx**2 * rng.uniform(0.7, 1.3, n)
    H = dx * rng.uniform(2.0, 3.5, n)
    gx, gy = centres(-0.2, 1.2, 35), centres(-0.1, 1.1, 24)
    out = shepard(pts, np.full(n, 3.7), vol, H, gx, gy, kernel=wendland_c2_2d)
    assert out.shape == (24, 35)
    ok = np.isfinite(out)
    assert ok.sum() > 0.5 * out.size
    np.testing.assert_allclose(out[ok], 3.7, rtol=0, atol=1e-13 * 3.7)
    # far outside the particles: no support
    assert np.isnan(out[:, 0]).all() and np.isnan(out[:, -1]).all()


def test_constant_reproduced_1d():
    rng = np.random.default_rng(2)
    x = np.sort(rng.uniform(0, 1, 200))
    dx = 1 / 200
    out = shepard(x, np.full(200, -2.5), dx, 3 * dx, centres(-0.5, 1.5, 80), kernel=wendland_c2_1d)
    assert out.shape == (80,)
    ok = np.isfinite(out)
    np.testing.assert_allclose(out[ok], -2.5, rtol=0, atol=1e-13 * 2.5)
    assert np.isnan(out[:5]).all() and np.isnan(out[-5:]).all()


def test_linear_field_exact_in_lattice_interior_2d():
    pts, dx = lattice_2d(40)
    H = 2.6 * dx
    f = 1.5 + 2.0 * pts[:, 0] - 0.75 * pts[:, 1]
    # output centres on lattice midpoints (spacing 2 dx): the lattice is symmetric about each
    gx = gy = centres(0.0, 1.0, 20)
    out = shepard(pts, f, dx**2, H, gx, gy, kernel=wendland_c2_2d)
    Y, X = np.meshgrid(gy, gx, indexing="ij")
    exact = 1.5 + 2.0 * X - 0.75 * Y
    interior = (X > H) & (X < 1 - H) & (Y > H) & (Y < 1 - H)
    assert interior.sum() >= 100
    np.testing.assert_allclose(out[interior], exact[interior], rtol=0, atol=1e-10)
    # at the edges Shepard is not exact for a linear field, but still defined
    assert np.isfinite(out).all()
    assert np.max(np.abs(out - exact)) > 1e-6


def test_linear_field_exact_in_lattice_interior_1d_on_particles_and_midpoints():
    n = 100
    dx = 1 / n
    x = centres(0, 1, n)
    f = 0.3 - 4.0 * x
    H = 3 * dx
    for gx in (centres(0, 1, 50), x):  # lattice midpoints, lattice sites
        out = shepard(x, f, dx, H, gx, kernel=wendland_c2_1d)
        interior = (gx > H) & (gx < 1 - H)
        np.testing.assert_allclose(out[interior], 0.3 - 4.0 * gx[interior], rtol=0, atol=1e-10)


def random_cloud(seed, n, H_range):
    """``n`` particles in the unit square: positions, two fields, volumes, supports."""
    rng = np.random.default_rng(seed)
    return (rng.uniform(0, 1, (n, 2)), rng.normal(size=(2, n)), rng.uniform(0.5, 1.5, n) / n,
            rng.uniform(*H_range, n))


def test_matches_brute_force_reference():
    pts, vals, vol, H = random_cloud(3, 150, (0.05, 0.2))
    gx, gy = centres(-0.1, 1.1, 17), centres(0, 1, 13)
    out = shepard(pts, vals, vol, H, gx, gy, kernel=wendland_c2_2d, min_support=0.05)
    ref = dense_shepard(pts, vals, vol, H, gx, gy, wendland_c2_2d, min_support=0.05)
    np.testing.assert_array_equal(np.isnan(out), np.isnan(ref))
    np.testing.assert_allclose(out, ref, rtol=1e-12, atol=1e-13)
    assert np.isnan(out).any() and np.isfinite(out).any()


def test_own_support_radius_per_particle():
    # particle 0: small support; particle 1: wide support
    x = np.array([0.0, 0.3])
    f = np.array([1.0, 2.0])
    H = np.array([0.1, 1.0])
    gx = np.array([0.05, 0.15])
    out = shepard(x, f, 1.0, H, gx, kernel=wendland_c2_1d, min_support=0)
    assert out[1] == 2.0  # 0.15 > H_0: only particle 1 reaches it
    w0, w1 = wendland_c2_1d(0.05, 0.1), wendland_c2_1d(0.25, 1.0)
    assert out[0] == pytest.approx((w0 * 1 + w1 * 2) / (w0 + w1), rel=1e-14)


def test_particle_on_a_cell_centre_counts():
    gx = centres(0, 1, 10)
    out = shepard(np.array([gx[3]]), np.array([5.0]), 0.1, 0.05, gx, kernel=wendland_c2_1d)
    assert out[3] == 5.0
    assert np.isnan(np.delete(out, 3)).all()


def test_min_support_threshold():
    gx = np.array([0.0, 0.5, 0.9])
    V, H = 0.1, 1.0
    den = V * wendland_c2_1d(gx, H)
    thr = 0.5 * (den[1] + den[2])  # between the two
    out = shepard(np.array([0.0]), np.array([4.0]), V, H, gx, kernel=wendland_c2_1d, min_support=thr)
    assert out[0] == 4.0 and out[1] == 4.0 and np.isnan(out[2])
    out = shepard(np.array([0.0]), np.array([4.0]), V, H, gx, kernel=wendland_c2_1d, min_support=0.0)
    assert (out == 4.0).all()


def test_no_particles_gives_nan():
    out = shepard(np.empty((0, 2)), np.empty((2, 0)), np.empty(0), np.empty(0),
                  centres(0, 1, 4), centres(0, 1, 3), kernel=wendland_c2_2d)
    assert out.shape == (2, 3, 4) and np.isnan(out).all()


# --- Shepard: shapes, batches, order -----------------------------------------


def test_batch_rows_equal_single_calls_and_shapes():
    rng = np.random.default_rng(4)
    pts, dx = lattice_2d(16)
    n = len(pts)
    vals = rng.normal(size=(3, n))
    gx, gy = centres(0, 1, 9), centres(0, 1, 7)
    out = shepard(pts, vals, dx**2, 3 * dx, gx, gy, kernel=wendland_c2_2d)
    assert out.shape == (3, 7, 9)
    for k in range(3):
        one = shepard(pts, vals[k], dx**2, 3 * dx, gx, gy, kernel=wendland_c2_2d)
        assert one.shape == (7, 9)
        np.testing.assert_allclose(out[k], one, rtol=1e-14, atol=1e-15)
    x = centres(0, 1, 50)
    out1 = shepard(x[:, None], np.vstack([x, x**2]), 0.02, 0.06, centres(0, 1, 10), kernel=wendland_c2_1d)
    assert out1.shape == (2, 10)


def test_result_independent_of_particle_order():
    pts, vals, vol, H = random_cloud(5, 400, (0.08, 0.15))
    n = len(H)
    gx, gy = centres(0, 1, 21), centres(0, 1, 19)
    a = shepard(pts, vals, vol, H, gx, gy, kernel=wendland_c2_2d, periodic=(True, False), box=((0, 1), (0, 1)))
    perm = np.random.default_rng(6).permutation(n)
    b = shepard(pts[perm], vals[:, perm], vol[perm], H[perm], gx, gy, kernel=wendland_c2_2d,
                periodic=(True, False), box=((0, 1), (0, 1)))
    np.testing.assert_array_equal(a, b)  # bit for bit


# --- Shepard: periodic images -------------------------------------------------


def test_periodic_wrap_1d_particle_near_lo_reaches_cells_near_hi():
    gx = centres(0, 1, 50)
    x, f = np.array([0.01]), np.array([7.0])
    plain = shepard(x, f, 0.02, 0.1, gx, kernel=wendland_c2_1d)
    wrapped = shepard(x, f, 0.02, 0.1, gx, kernel=wendland_c2_1d, periodic=[True], box=[(0.0, 1.0)])
    assert np.isnan(plain[-1]) and wrapped[-1] == 7.0
    near_hi = gx > 0.95
    assert np.isfinite(wrapped[near_hi]).all()


def test_periodic_equals_explicit_images_2d():
    rng = np.random.default_rng(6)
    n = 120
    box = ((0.0, 1.0), (-0.5, 0.5))
    pts = np.column_stack([rng.uniform(0, 1, n), rng.uniform(-0.5, 0.5, n)])
    vals = rng.normal(size=n)
    vol = np.full(n, 1.0 / n)
    H = rng.uniform(0.1, 0.25, n)
    gx, gy = centres(0, 1, 12), centres(-0.5, 0.5, 10)
    per = shepard(pts, vals, vol, H, gx, gy, kernel=wendland_c2_2d, periodic=(True, True), box=box)
    shifts = [(sx, sy) for sx in (-1, 0, 1) for sy in (-1, 0, 1)]
    img = np.concatenate([pts + np.array(s) for s in shifts])
    ref = shepard(img, np.tile(vals, 9), np.tile(vol, 9), np.tile(H, 9), gx, gy, kernel=wendland_c2_2d)
    np.testing.assert_allclose(per, ref, rtol=1e-12, atol=1e-14)
    assert np.isfinite(per).all()


def test_periodic_support_wider_than_box_sums_all_images():
    L = 0.5
    x = np.array([0.1, 0.3])
    f = np.array([1.0, 3.0])
    gx = centres(0, L, 5)
    per = shepard(x, f, 0.2, 1.3, gx, kernel=wendland_c2_1d, periodic=[True], box=[(0, L)])
    k = np.arange(-4, 5)
    img = (x[None, :] + L * k[:, None]).ravel()
    ref = dense_shepard(img, np.tile(f, k.size), 0.2, 1.3, gx, None, wendland_c2_1d)
    np.testing.assert_allclose(per, ref, rtol=1e-13)


def test_periodic_positions_outside_box_are_wrapped_and_input_untouched():
    gx = centres(0, 1, 20)
    x_out = np.array([1.01, -0.2])
    x_in = np.array([0.01, 0.8])
    f = np.array([1.0, 2.0])
    kw = {"kernel": wendland_c2_1d, "periodic": [True], "box": [(0, 1)]}
    a = shepard(x_out, f, 0.1, 0.3, gx, **kw)
    b = shepard(x_in, f, 0.1, 0.3, gx, **kw)
    np.testing.assert_allclose(a, b, rtol=1e-12)
    assert x_out[0] == 1.01  # the caller's array is not wrapped in place


def test_periodic_constant_field_defined_everywhere():
    pts, dx = lattice_2d(20)
    gx = gy = centres(0, 1, 10)
    out = shepard(pts, np.ones(len(pts)), dx**2, 2.5 * dx, gx, gy, kernel=wendland_c2_2d,
                  periodic=(True, True), box=((0, 1), (0, 1)))
    np.testing.assert_allclose(out, 1.0, atol=1e-13)


# --- Shepard: bad input ---------------------------------------------------------


def one_sentence(err) -> str:
    message = str(err)
    assert message and "\n" not in message
    return message


GOOD = {"points": np.zeros((3, 2)), "values": np.ones(3), "volumes": 1.0, "support": 0.5,
            "grid_x": centres(0, 1, 4), "grid_y": centres(0, 1, 4), "kernel": wendland_c2_2d}


@pytest.mark.parametrize("change, name", [
    ({"points": np.zeros((3, 3))}, "points"),
    ({"points": np.full((3, 2), np.nan)}, "points"),
    ({"values": np.ones(4)}, "values"),
    ({"volumes": -1.0}, "volumes"),
    ({"volumes": np.ones(2)}, "volumes"),
    ({"support": 0.0}, "support"),
    ({"grid_x": [0.0, 0.0, 1.0]}, "grid_x"),
    ({"grid_y": np.ones((2, 2))}, "grid_y"),
    ({"kernel": None}, "kernel"),
    ({"kernel": lambda r, H: np.ones(3)}, "kernel"),
    ({"kernel": lambda r, H: np.full_like(r, np.inf)}, "kernel"),
    ({"min_support": 1.5}, "min_support"),
    ({"periodic": (True,)}, "periodic"),
    ({"periodic": (True, False)}, "box"),
    ({"periodic": (True, False), "box": ((1, 0), (0, 1))}, "box"),
])
def test_shepard_bad_input(change, name):
    with pytest.raises(InputError) as info:
        shepard(**{**GOOD, **change})
    assert name in one_sentence(info.value)


# --- DSMC: cell sums ------------------------------------------------------------


def test_cell_sums_hand_placed_1d():
    gx = np.array([0.5, 1.5, 2.5])  # edges 0, 1, 2, 3
    x = np.array([0.0, 0.99, 1.0, 2.999, 3.0, -0.1, 1.5])
    w = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0])
    q = np.array([[1.0] * 7, [10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0]])
    sums, counts = cell_average(x, w, q, gx)
    np.testing.assert_array_equal(counts, [2, 2, 1])  # a point on an edge goes to the upper cell
    np.testing.assert_array_equal(sums, [[3.0, 10.0, 4.0], [50.0, 90.0 + 490.0, 160.0]])
    s1, c1 = cell_average(x[:, None], w, q[1], gx)
    np.testing.assert_array_equal(s1, sums[1])
    np.testing.assert_array_equal(c1, counts)


def test_cell_sums_hand_placed_2d():
    gx = np.array([0.0, 1.0, 2.0])  # x edges -0.5, 0.5, 1.5, 2.5
    gy = np.array([10.0, 12.0])  # y edges 9, 11, 13
    pts = np.array([
        [0.0, 10.0],   # (0, 0)
        [0.4, 9.0],    # (0, 0)
        [1.2, 12.9],   # (1, 1)  (iy, ix)
        [2.49, 11.0],  # (1, 2)
        [2.5, 10.0],   # outside in x
        [1.0, 8.99],   # outside in y
    ])
    w = np.array([1.0, 2.0, 4.0, 8.0, 16.0, 32.0])
    q = np.array([1.0, 3.0, 5.0, 7.0, 9.0, 11.0])
    sums, counts = cell_average(pts, w, q, gx, gy)
    assert sums.shape == counts.shape == (2, 3)
    np.testing.assert_array_equal(counts, [[2, 0, 0], [0, 1, 1]])
    np.testing.assert_array_equal(sums, [[7.0, 0.0, 0.0], [0.0, 20.0, 56.0]])
    assert counts.dtype.kind == "i"


def test_cell_sums_conserve_what_lies_inside():
    rng = np.random.default_rng(7)
    n = 20000
    gx, gy = centres(0, 2, 16), centres(-1, 1, 11)
    pts = np.column_stack([rng.uniform(-0.3, 2.3, n), rng.uniform(-1.2, 1.2, n)])
    w = rng.uniform(0.5, 2.0, n)
    q = rng.normal(size=(3, n))
    sums, counts = cell_average(pts, w, q, gx, gy)
    inside = (pts[:, 0] >= 0) & (pts[:, 0] < 2) & (pts[:, 1] >= -1) & (pts[:, 1] < 1)
    np.testing.assert_allclose(sums.sum(axis=(1, 2)), (w * q)[:, inside].sum(axis=1), rtol=1e-11, atol=1e-9)
    assert counts.sum() == inside.sum()
    assert inside.sum() < n  # some were dropped


def test_cell_average_is_order_independent():
    rng = np.random.default_rng(8)
    pts = rng.uniform(0, 1, (500, 2))
    w, q = rng.uniform(1, 2, 500), rng.normal(size=(2, 500))
    gx = gy = centres(0, 1, 5)
    a, ca = cell_average(pts, w, q, gx, gy)
    perm = rng.permutation(500)
    b, cb = cell_average(pts[perm], w[perm], q[:, perm], gx, gy)
    np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-13)
    np.testing.assert_array_equal(ca, cb)


# --- DSMC: moments → primitive variables -----------------------------------------

K_B = 1.380649e-23
M_AIR = 28.97e-3 / 6.02214076e23


def gas_cells(U=(0.0, 0.0), T=300.0, per_cell=6, FN=1e18):
    """A uniform diatomic gas: in every cell of a 4 × 3 grid, six particles with
    thermal velocities ±s along x, y and z (|c'|² = 3kT/m) and internal energy
    kT (ζ = 2), on top of the bulk velocity U."""
    gx, gy = centres(0, 0.4, 4), centres(0, 0.3, 3)
    Y, X = np.meshgrid(gy, gx, indexing="ij")
    s = np.sqrt(3 * K_B * T / M_AIR)
    dirs = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    c = np.tile(s * dirs, (X.size, 1)) + np.array([U[0], U[1], 0.0])
    pts = np.repeat(np.column_stack([X.ravel(), Y.ravel()]), 6, axis=0)
    e_int = np.full(len(pts), K_B * T)
    w = np.full(len(pts), FN * M_AIR)
    q = np.vstack([np.ones(len(pts)), c[:, 0], c[:, 1], 0.5 * (c**2).sum(axis=1) + e_int / M_AIR])
    volume = 0.1 * 0.1 * 1.0  # cell area × 1 m depth
    return pts, w, q, gx, gy, volume


def test_uniform_gas_at_rest_gives_back_rho_and_p():
    T, FN = 300.0, 1e18
    pts, w, q, gx, gy, V = gas_cells(T=T, FN=FN)
    sums, counts = cell_average(pts, w, q, gx, gy)
    assert (counts == 6).all()
    rho, u, v, p, e = moments_to_primitive(sums[0], sums[1:3], sums[3], V, 1.4)
    N = 6 * FN
    np.testing.assert_allclose(rho, N * M_AIR / V, rtol=1e-13)
    np.testing.assert_allclose(p, N * K_B * T / V, rtol=1e-12)  # p = n k T
    np.testing.assert_allclose(e, K_B * T / (0.4 * M_AIR), rtol=1e-12)  # e = c_v T
    np.testing.assert_allclose(u, 0.0, atol=1e-9)
    np.testing.assert_allclose(v, 0.0, atol=1e-9)


def test_moving_gas_velocity_and_galilean_pressure():
    pts, w, q, gx, gy, V = gas_cells(U=(250.0, -40.0))
    sums, _ = cell_average(pts, w, q, gx, gy)
    _rho, u, v, p, _e = moments_to_primitive(sums[0], sums[1:3], sums[3], V, 1.4)
    np.testing.assert_allclose(u, 250.0, rtol=1e-12)
    np.testing.assert_allclose(v, -40.0, rtol=1e-12)
    np.testing.assert_allclose(p, 6e18 * K_B * 300.0 / V, rtol=1e-9)


def test_time_window_sums_with_volume_times_samples():
    pts, w, q, gx, gy, V = gas_cells()
    sums, _ = cell_average(pts, w, q, gx, gy)
    one = moments_to_primitive(sums[0], sums[1:3], sums[3], V, 1.4)
    five = moments_to_primitive(5 * sums[0], 5 * sums[1:3], 5 * sums[3], 5 * V, 1.4)
    for a, b in zip(one, five):
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-9)


def test_moments_1d_and_empty_cells():
    M = np.array([2.0, 0.0, 1.0])
    P = np.array([4.0, 0.0, -1.0])  # same shape as mass: one component
    E = np.array([10.0, 0.0, 3.0])
    rho, u, p, e = moments_to_primitive(M, P, E, 0.5, 5 / 3)
    np.testing.assert_allclose(rho, [4.0, 0.0, 2.0])
    np.testing.assert_allclose(u[[0, 2]], [2.0, -1.0])
    np.testing.assert_allclose(e[[0, 2]], [(10 - 4) / 2, (3 - 0.5) / 1])
    np.testing.assert_allclose(p, [(2 / 3) * 6 / 0.5, 0.0, (2 / 3) * 2.5 / 0.5])
    assert np.isnan(u[1]) and np.isnan(e[1])
    out3 = moments_to_primitive(M, np.stack([P, P, P]), 3 * E, 0.5, 1.4)
    assert len(out3) == 6  # rho, u, v, w, p, e


def test_uniform_gas_maxwellian_sample():
    """A sampled Maxwellian gas at rest: ρ exact, p = n k T to sampling error."""
    rng = np.random.default_rng(9)
    T, n, FN = 250.0, 400000, 1e15
    gx = centres(0, 1, 4)
    x = rng.uniform(0, 1, n)
    c = rng.normal(0, np.sqrt(K_B * T / M_AIR), (n, 3))
    e_int = rng.exponential(K_B * T, n)  # ζ = 2: ε_int ~ kT Exp(1)
    q = np.vstack([np.ones(n), c[:, 0], 0.5 * (c**2).sum(axis=1) + e_int / M_AIR])
    sums, counts = cell_average(x, FN * M_AIR, q, gx)
    V = 0.25 * 1.0 * 1.0
    rho, _u, p, _e = moments_to_primitive(sums[0], sums[1], sums[2], V, 1.4)
    np.testing.assert_allclose(rho, counts * FN * M_AIR / V, rtol=1e-10)
    np.testing.assert_allclose(p, counts * FN * K_B * T / V, rtol=0.01)


@pytest.mark.parametrize("call, name", [
    (lambda: cell_average(np.zeros(3), np.ones(3), np.ones(3), [0.5]), "grid_x"),
    (lambda: cell_average(np.zeros(3), np.ones(3), np.ones(3), [0.0, 1.0, 3.0]), "grid_x"),
    (lambda: cell_average(np.zeros((3, 2)), np.ones(3), np.ones(3), [0.0, 1.0]), "points"),
    (lambda: cell_average(np.zeros(3), -np.ones(3), np.ones(3), [0.0, 1.0]), "weights"),
    (lambda: cell_average(np.zeros(3), np.ones(3), np.ones((2, 4)), [0.0, 1.0]), "quantities"),
    (lambda: cell_average(np.zeros(3), np.ones(3), [1, np.nan, 1], [0.0, 1.0]), "quantities"),
    (lambda: moments_to_primitive([1.0], [0.0], [1.0], 1.0, 1.0), "gamma"),
    (lambda: moments_to_primitive([1.0], [0.0], [1.0], 0.0, 1.4), "volume"),
    (lambda: moments_to_primitive([-1.0], [0.0], [1.0], 1.0, 1.4), "mass"),
    (lambda: moments_to_primitive([1.0], [0.0], [-1.0], 1.0, 1.4), "energy"),
    (lambda: moments_to_primitive([1.0, 2.0], np.zeros((4, 2)), [1.0, 1.0], 1.0, 1.4), "momentum"),
    (lambda: moments_to_primitive([1.0, 2.0], [0.0, 0.0], [1.0], 1.0, 1.4), "energy"),
    (lambda: moments_to_primitive([1.0, 2.0], [0.0, 0.0], [1.0, 1.0], [1.0, 1.0, 1.0], 1.4), "volume"),
])
def test_cell_average_and_moments_bad_input(call, name):
    with pytest.raises(InputError) as info:
        call()
    assert name in one_sentence(info.value)


def test_compare_deposit_imports_no_other_partmesh_package():
    import subprocess
    import sys

    code = ("import sys, partmesh.compare.deposit; "
            "bad = [m for m in ('cases', 'gridref', 'particle') if m in sys.modules]; "
            "sys.exit(1 if bad else 0)")
    assert subprocess.run([sys.executable, "-c", code], check=False).returncode == 0
