"""The SPH solver's Shepard fast paths (partmesh.particle.sph.sampling) against the
general deposition partmesh.compare.deposit.shepard: same kernel, same particles,
same cells, sums equal to round-off; periodic axes wrap."""

import numpy as np
import pytest

from partmesh.compare.deposit import shepard
from partmesh.particle import kernels
from partmesh.particle.sph.sampling import on_grid, shepard_at_points

KIND = kernels.KERNELS["wendland_c6"]


def _cloud(dim, n, rng):
    """Particles scattered over [0, 1]^dim and a little beyond (so some cells see
    no particle at all), random supports, volumes and two fields."""
    x = rng.uniform(-0.1, 1.1, (n, dim))
    H = rng.uniform(0.03, 0.09, n)
    vol = rng.uniform(0.5, 1.5, n) / n
    values = np.stack([np.sin(3 * x[:, 0]) + x[:, -1], rng.normal(size=n)])
    return x, H, vol, values


@pytest.mark.parametrize("periodic", [(False, False), (True, False), (False, True), (True, True)])
def test_grid_deposition_matches_the_general_shepard_2d(periodic):
    rng = np.random.default_rng(3)
    x, H, vol, values = _cloud(2, 3000, rng)
    x = x[(x[:, 0] > 0.3) | (x[:, 1] > 0.3)]  # a hole: cells without support must come out NaN
    H, vol, values = H[: len(x)], vol[: len(x)], values[:, : len(x)]
    gx, gy = (np.arange(40) + 0.5) / 40, (np.arange(25) + 0.5) / 25
    reference = shepard(x, values, vol, H, gx, gy, kernel=lambda r, h: kernels.w("wendland_c6", r, h, 2),
                        periodic=periodic, box=((0.0, 1.0), (0.0, 1.0)))
    fast = on_grid(x, values, vol, H, (gx, gy), periodic, KIND, 1e-3)
    assert np.isnan(reference).any() and not np.isnan(reference).all()
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(reference))
    np.testing.assert_allclose(fast, reference, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("periodic", [False, True])
def test_grid_deposition_matches_the_general_shepard_1d(periodic):
    rng = np.random.default_rng(4)
    x, H, vol, values = _cloud(1, 400, rng)
    gx = (np.arange(64) + 0.5) / 64
    reference = shepard(x, values, vol, H, gx, kernel=lambda r, h: kernels.w("wendland_c6", r, h, 1),
                        periodic=(periodic,), box=((0.0, 1.0),))
    fast = on_grid(x, values, vol, H, (gx,), (periodic,), KIND, 1e-3)
    np.testing.assert_allclose(fast, reference, rtol=1e-12, atol=1e-12)


def _all_pairs_3d(x, values, vol, H, axes, periodic):
    """Σ_j f_j V_j W / Σ_j V_j W at every cell of ``axes`` over every particle
    (minimum image on the periodic axes of the unit cube), NaN below 1e-3."""
    Z, Y, X = np.meshgrid(axes[2], axes[1], axes[0], indexing="ij")
    d = np.stack([X, Y, Z], axis=-1)[..., None, :] - x
    d -= np.asarray(periodic) * np.round(d)
    W = vol * kernels.w("wendland_c6", np.linalg.norm(d, axis=-1), H, 3)
    den = W.sum(axis=-1)
    with np.errstate(invalid="ignore"):
        return np.where(den >= 1e-3, np.einsum("zyxn,kn->kzyx", W, values) / den, np.nan)


def _centres(n):
    return (np.arange(n) + 0.5) / n


@pytest.mark.parametrize("periodic", [(False, False, False), (True, False, True), (False, True, False),
                                      (True, True, True)])
@pytest.mark.parametrize("shape, wide", [((13, 9, 11), 1.5), ((13, 9, 1), 1.5), ((6, 4, 4), 5.0)])
def test_grid_deposition_in_3d_matches_the_sum_over_all_pairs(periodic, shape, wide):
    """The 3D grid against the sums over every particle and cell: unequal
    spacings, one layer of a single cell, and even cell counts on periodic
    axes with supports near half the period (every plane and row once)."""
    rng = np.random.default_rng(8)
    x, H, vol, values = _cloud(3, 1500, rng)
    x = x[np.linalg.norm(x - 0.7, axis=1) > 0.35]  # a hole: cells without support come out NaN
    H, vol, values = wide * H[: len(x)], vol[: len(x)], values[:, : len(x)]
    grid = tuple(_centres(n) for n in shape)
    reference = _all_pairs_3d(x, values, vol, H, grid, periodic)
    fast = on_grid(x, values, vol, H, grid, periodic, KIND, 1e-3, lengths=(1.0, 1.0, 1.0))
    assert fast.shape == (2, shape[2], shape[1], shape[0])
    assert not np.isnan(reference).all()
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(reference))
    np.testing.assert_allclose(fast, reference, rtol=1e-12, atol=1e-12)


def test_point_sampling_matches_the_general_shepard():
    rng = np.random.default_rng(5)
    x, H, vol, values = _cloud(2, 2000, rng)
    gx, gy = np.array([0.2, 0.5, 0.77]), np.array([0.31, 0.64])
    reference = shepard(x, values[0], vol, H, gx, gy, kernel=lambda r, h: kernels.w("wendland_c6", r, h, 2))
    X, Y = np.meshgrid(gx, gy)
    points = np.column_stack([X.ravel(), Y.ravel()])
    sampled = shepard_at_points(points, x, values[0], vol, H, KIND, 2, 3)
    np.testing.assert_allclose(sampled, reference.ravel(), rtol=1e-12)
