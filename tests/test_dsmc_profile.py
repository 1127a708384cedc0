"""The linear profile of the DSMC redraw (partmesh.particle.dsmc.profile):
MC-limited slopes against a brute-force loop, exact conservation of each cell's
momentum and energy about the profile, the profile and the temperature
recovered from the redrawn particles, the cap on the profile's energy, the
refusals (a gas at rest under the profile: test_dsmc_axisymmetric, test_dsmc)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import partmesh
from partmesh.cases.errors import InputError
from partmesh.particle.dsmc.axisymmetric import resampled_redraw
from partmesh.particle.dsmc.equilibrate import equilibrate
from partmesh.particle.dsmc.intervals import EVERY_CELL
from partmesh.particle.dsmc.profile import (
    MAX_PROFILE_SHARE,
    NO_SLOPES,
    cell_means,
    limited_slopes,
)


def _mc(a, b):
    """minmod(2a, 2b, (a + b)/2), written out."""
    return 0.0 if a * b <= 0.0 else math.copysign(min(abs(0.5 * (a + b)), 2.0 * min(abs(a), abs(b))), a)


def _slopes_by_loop(count, mean, shape, spacing, periodic):
    """The MC-limited slope of every cell, quantity and axis, one at a time."""
    nx, ny = shape
    out = np.zeros((nx * ny, 2, 4))
    for j in range(ny):
        for i in range(nx):
            c = i + nx * j
            for a, (di, dj) in enumerate(((1, 0), (0, 1))):
                ahead, behind = (i + di, j + dj), (i - di, j - dj)
                if periodic[a]:
                    ahead, behind = (ahead[0] % nx, ahead[1] % ny), (behind[0] % nx, behind[1] % ny)
                cells = []
                for ii, jj in (ahead, behind):
                    inside = 0 <= ii < nx and 0 <= jj < ny
                    cells.append(ii + nx * jj if inside and count[ii + nx * jj] >= 2 else None)
                if count[c] < 2 or None in cells:
                    continue
                for q in range(4):
                    out[c, a, q] = _mc(mean[cells[0], q] - mean[c, q], mean[c, q] - mean[cells[1], q]) / spacing[a]
    return out


@pytest.mark.parametrize("periodic", [(False, False), (True, False), (False, True), (True, True)])
def test_limited_slopes_are_the_mc_limit_of_the_neighbour_differences_none_at_an_edge_or_an_empty_cell(periodic):
    rng = np.random.default_rng(3)
    shape, spacing = (7, 5), np.array([0.5, 2.0])
    count = np.where(rng.random(35) < 0.2, rng.integers(0, 2, 35), 5)  # a fifth of the cells hold 0 or 1
    count[:7] = 5
    mean = rng.normal(size=(35, 4))
    mean[:7] = np.linspace(0.0, 1.0, 7)[:, None] ** 3  # a monotone row: the central difference, or twice the smaller
    got = limited_slopes(count, mean, shape, spacing, periodic)
    np.testing.assert_array_equal(got, _slopes_by_loop(count, mean, shape, spacing, periodic))
    assert np.count_nonzero(got) > 30


@pytest.mark.parametrize("periodic", [False, True])
def test_limited_slopes_on_a_line_are_those_of_a_one_row_grid(periodic):
    # a row of 12 cells is a 12 x 1 grid whose second axis has no neighbours: the loop's x slopes
    rng = np.random.default_rng(5)
    count = np.array([5, 5, 5, 1, 5, 5, 5, 0, 5, 5, 5, 5])
    mean = rng.normal(size=(12, 4))
    mean[:, 0] = np.cumsum(rng.uniform(0.1, 1.0, 12))  # rising: a slope wherever both neighbours hold two or more
    got = limited_slopes(count, mean, (12,), np.array([0.25]), (periodic,))
    want = _slopes_by_loop(count, mean, (12, 1), np.array([0.25, 1.0]), (periodic, False))
    assert got.shape == (12, 1, 4)
    np.testing.assert_array_equal(got, want[:, :1, :])
    assert np.count_nonzero(got[:, 0, 0]) == 4  # cells 1, 5, 9, 10


def _cell_of_particles(rng, N, slopes, dim=2):
    """One cell [0, 1]^dim of N particles, unit thermal spread, bulk velocity (3, -1, 0.5)."""
    x = rng.uniform(0.0, 1.0, (N, dim))
    v = np.array([3.0, -1.0, 0.5]) + rng.normal(size=(N, 3))
    e = rng.gamma(1.0, 1.0, N)
    return x, v, e, np.array([0, N]), np.asarray(slopes, float).reshape(1, dim, 4)


def _sums(v, e, w=None):
    w = np.ones(len(v)) if w is None else w
    return w.sum(), (w[:, None] * v).sum(axis=0), (w * (0.5 * (v * v).sum(axis=1) + e)).sum()


@settings(max_examples=40, deadline=None)
@given(N=st.integers(2, 80), seed=st.integers(0, 2**32 - 1), steep=st.floats(0.0, 30.0),
       zeta=st.sampled_from([0.0, 2.0]))
def test_the_redraw_about_a_profile_conserves_the_cells_momentum_and_energy_to_round_off(N, seed, steep, zeta):
    # steep slopes hit the cap on the profile's share of the heat and the bounds on the temperature ratio
    rng = np.random.default_rng(seed)
    slopes = steep * rng.normal(size=(2, 4))
    x, v, e, start, slopes = _cell_of_particles(rng, N, slopes)
    e = e if zeta > 0 else np.zeros(N)
    before = _sums(v, e)
    v1, e1 = v.copy(), e.copy()
    equilibrate(x, v1, e1, start, zeta, seed, 1, np.zeros(1), np.zeros((1, 3)), np.zeros(1), slopes, EVERY_CELL)
    after = _sums(v1, e1)
    scale = before[0] * (np.abs(before[1] / before[0]).sum() + np.sqrt(2 * before[2] / before[0]))
    np.testing.assert_allclose(after[1], before[1], rtol=0, atol=1e-12 * scale)
    assert after[2] == pytest.approx(before[2], rel=1e-12)
    assert np.all(e1 >= 0.0)


def test_the_resampled_redraw_about_a_profile_conserves_mass_momentum_and_energy_to_round_off():
    rng = np.random.default_rng(8)
    x, v, e, start, slopes = _cell_of_particles(rng, 60, 5.0 * rng.normal(size=(2, 4)))
    w = rng.uniform(0.5, 3.0, 60)
    before = _sums(v, e, w)
    xs, vs, es, ws, new = resampled_redraw(x, v, e, w, start, np.array([2.0]), 2.0, 4, 9, np.zeros(1),
                                           np.zeros((1, 3)), np.zeros(1), slopes=slopes)
    after = _sums(vs, es, ws)
    assert after[0] == pytest.approx(before[0], rel=1e-14)
    np.testing.assert_allclose(after[1], before[1], rtol=1e-12)
    assert after[2] == pytest.approx(before[2], rel=1e-12)


def test_the_redrawn_particles_carry_the_velocity_and_temperature_profiles():
    # 200 000 particles in one cell: the least-squares slope of each velocity component against x and y is
    # the given slope, and θ in four strips across x is θ_c + g·(x̄_strip - x̄)
    rng = np.random.default_rng(4)
    N, zeta = 200_000, 2.0
    G = np.array([[0.8, -0.3, 0.1, 0.4], [0.2, 0.5, 0.0, -0.2]])  # (axis, quantity): dU/dx, dU/dy, dθ/dx, dθ/dy
    x, v, e, start, slopes = _cell_of_particles(rng, N, G)
    U_before = v.mean(axis=0)
    equilibrate(x, v, e, start, zeta, 11, 2, np.zeros(1), np.zeros((1, 3)), np.zeros(1), slopes, EVERY_CELL)
    design = np.column_stack([np.ones(N), x - x.mean(axis=0)])
    fitted = np.linalg.lstsq(design, v, rcond=None)[0]  # rows: intercept, d/dx, d/dy
    np.testing.assert_allclose(fitted[1:], G[:, :3], atol=0.04)  # (standard error 0.008)
    U = v.mean(axis=0)
    np.testing.assert_allclose(U, U_before, atol=1e-12)
    profile = U + (x - x.mean(axis=0)) @ G[:, :3]
    heat = 0.5 * ((v - profile) ** 2).sum(axis=1) + e
    theta_c = 2.0 * heat.mean() / (3.0 + zeta)
    strips = np.minimum((x[:, 0] * 4).astype(int), 3)
    for k in range(4):
        inside = strips == k
        theta = 2.0 * heat[inside].mean() / (3.0 + zeta)
        expected = theta_c + G[0, 3] * (x[inside, 0].mean() - x[:, 0].mean()) + G[1, 3] * (
            x[inside, 1].mean() - x[:, 1].mean())
        assert theta == pytest.approx(expected, rel=0.01)


def test_a_profile_steeper_than_the_heat_allows_is_scaled_to_take_its_cap():
    rng = np.random.default_rng(5)
    N = 50_000
    x, v, e, start, slopes = _cell_of_particles(rng, N, [[40.0, 0, 0, 0], [0, 0, 0, 0]])
    before = _sums(v, e)
    thermal = before[2] - 0.5 * (before[1] ** 2).sum() / N
    equilibrate(x, v, e, start, 2.0, 3, 1, np.zeros(1), np.zeros((1, 3)), np.zeros(1), slopes, EVERY_CELL)
    d = x[:, 0] - x[:, 0].mean()
    f = np.dot(v[:, 0] - v[:, 0].mean(), d) / np.dot(d, d) / 40.0  # the scale of the slope the draw kept
    profile_energy = 0.5 * (f * 40.0) ** 2 * np.dot(d, d)
    assert profile_energy == pytest.approx(MAX_PROFILE_SHARE * thermal, rel=0.01)


def test_cell_means_are_the_weighted_velocity_and_temperature_of_each_cell():
    rng = np.random.default_rng(6)
    sizes = [3, 0, 1, 40]
    start = np.concatenate([[0], np.cumsum(sizes)])
    v, e, w = rng.normal(size=(44, 3)), rng.gamma(1.0, 1.0, 44), rng.uniform(0.5, 2.0, 44)
    count, mean = cell_means(v, e, w, start, 2.0)
    np.testing.assert_array_equal(count, sizes)
    for c in (0, 2, 3):
        s = slice(start[c], start[c + 1])
        U = np.average(v[s], axis=0, weights=w[s])
        heat = (w[s] * (0.5 * ((v[s] - U) ** 2).sum(axis=1) + e[s])).sum()
        np.testing.assert_allclose(mean[c], [*U, heat / (2.5 * w[s].sum())], rtol=1e-12)
    np.testing.assert_array_equal(mean[1], 0.0)


@pytest.mark.parametrize("slopes", [NO_SLOPES, np.zeros((1, 1, 4)), np.full((1, 1, 4), 0.5)])
def test_a_cell_without_heat_keeps_its_velocity_whatever_the_profile(slopes):
    # three particles of one velocity: the heat Σ½|v|² − ½N|U|² rounds to a few 1e-14 below zero
    x, v, e = np.array([[0.1], [0.5], [0.9]]), np.tile([0.3, 1e3, -7.0], (3, 1)), np.zeros(3)
    equilibrate(x, v, e, np.array([0, 3]), 0.0, 1, 1, np.zeros(1), np.zeros((1, 3)), np.zeros(1), slopes, EVERY_CELL)
    assert np.all(np.isfinite(v))
    np.testing.assert_allclose(v, np.tile([0.3, 1e3, -7.0], (3, 1)), rtol=1e-9)


@pytest.mark.parametrize("settings, words", [
    ({"profile": "cubic"}, "profile must be one of"),
    ({"profile": "linear", "collisions": "larsen-borgnakke", "mean_free_path": 1e-3}, "applies only to"),
])
def test_a_profile_the_redraw_cannot_draw_is_refused_in_one_sentence(settings, words):
    with pytest.raises(InputError, match=words) as refused:
        partmesh.run("sod", "dsmc", dx=0.05, progress=False, **settings)
    assert str(refused.value).count(". ") == 0 and "profile" in str(refused.value)
