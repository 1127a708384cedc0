"""The DSMC equilibrium redraw (partmesh.particle.dsmc.equilibrate): exact
conservation of each cell's momentum and energy, Maxwellian velocities and
Gamma-distributed internal energies, reproducibility from the seed; and the
cell sort it works on (partmesh.particle.dsmc.cells)."""

import numba
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from partmesh.particle.dsmc import random
from partmesh.particle.dsmc.cells import sort_into_cells
from partmesh.particle.dsmc.equilibrate import equilibrate
from partmesh.particle.dsmc.intervals import EVERY_CELL
from partmesh.particle.dsmc.profile import NO_SLOPES
from partmesh.particle.dsmc.random import gamma, normal, stream, uniform


def _cells(sizes, rng, bulk=1.0, zeta=2.0):
    """Particles of cells with ``sizes`` particles each, in cell order:
    far-from-equilibrium velocities (uniform in a box around each cell's bulk
    velocity) and internal energies."""
    cell = np.repeat(np.arange(len(sizes)), sizes)
    n = cell.size
    U = rng.normal(0.0, bulk, (len(sizes), 3))
    v = U[cell] + rng.uniform(-1.0, 1.0, (n, 3)) * rng.uniform(0.1, 3.0, len(sizes))[cell, None]
    e = rng.uniform(0.0, 2.0, n) if zeta > 0 else np.zeros(n)
    start = np.concatenate([[0], np.cumsum(sizes)])
    return v, e, cell, start


def _redraw(v, e, start, zeta, seed, step):
    """Redraw in place about each cell's mean velocity (no profile: the
    positions are not read); returns the per-cell sums the redraw reports."""
    ncell = start.size - 1
    count, momentum, energy = np.zeros(ncell), np.zeros((ncell, 3)), np.zeros(ncell)
    equilibrate(np.zeros((v.shape[0], 1)), v, e, start, zeta, seed, step, count, momentum, energy, NO_SLOPES,
                EVERY_CELL)
    return count, momentum, energy


def _moments(v, e, cell, ncell, zeta):
    """Per cell: particle count, Σ v (3), Σ (½|v|² + e)."""
    count = np.bincount(cell, minlength=ncell)
    momentum = np.stack([np.bincount(cell, v[:, a], minlength=ncell) for a in range(3)], axis=1)
    energy = np.bincount(cell, 0.5 * (v * v).sum(axis=1) + (e if zeta > 0 else 0.0), minlength=ncell)
    return count, momentum, energy


@settings(max_examples=60, deadline=None)
@given(sizes=st.lists(st.integers(1, 60), min_size=1, max_size=30), bulk=st.floats(0.0, 1e3),
       zeta=st.sampled_from([0.0, 2.0, 3.0]), seed=st.integers(0, 2**63 - 1))
def test_redraw_conserves_each_cells_momentum_and_energy_to_round_off(sizes, bulk, zeta, seed):
    rng = np.random.default_rng(seed % 2**32)
    v, e, cell, start = _cells(sizes, rng, bulk, zeta)
    before = _moments(v, e, cell, len(sizes), zeta)
    v1, e1 = v.copy(), e.copy()
    reported = _redraw(v1, e1, start, zeta, seed, 7)
    after = _moments(v1, e1, cell, len(sizes), zeta)
    for sums, sums_before in zip(reported, before):  # the sums it reports are the cells' before the redraw
        np.testing.assert_allclose(sums, sums_before, rtol=1e-13, atol=1e-13 * np.abs(before[1]).max())
    np.testing.assert_array_equal(after[0], before[0])
    thermal = np.sqrt(2.0 * before[2] / before[0])  # a velocity scale of each cell
    scale = np.abs(before[1]).sum(axis=1) + before[0] * thermal
    assert np.all(np.abs(after[1] - before[1]).max(axis=1) <= 1e-12 * scale)
    assert np.all(np.abs(after[2] - before[2]) <= 1e-12 * before[2])
    # a lone particle keeps its state; the others are redrawn
    lone = np.flatnonzero(np.asarray(sizes)[cell] == 1)
    np.testing.assert_array_equal(v1[lone], v[lone])
    crowded = np.flatnonzero(np.asarray(sizes)[cell] >= 2)
    assert np.all(np.any(v1[crowded] != v[crowded], axis=1))


def _standardised(zeta, rng, cells=500, size=200):
    """Velocities minus the cell's bulk velocity and internal energies, both in
    units of the cell's θ = 2 E_th / ((3 + ζ) N), before and after the redraw."""
    v, e, cell, start = _cells([size] * cells, rng, 5.0, zeta)
    out = []
    for redraw in (False, True):
        if redraw:
            _redraw(v, e, start, zeta, 123, 1)
        count, momentum, energy = _moments(v, e, cell, cells, zeta)
        U = momentum / count[:, None]
        theta = 2.0 * (energy - 0.5 * count * (U * U).sum(axis=1)) / ((3.0 + zeta) * count)
        out.append(((v - U[cell]) / np.sqrt(theta[cell, None]), e / theta[cell]))
    return out


@pytest.mark.parametrize("zeta", [0.0, 2.0])
def test_redrawn_velocities_are_maxwellian_and_internal_energies_gamma(zeta):
    (c_in, e_in), (c_out, e_out) = _standardised(zeta, np.random.default_rng(1))
    # the test has the power to see a non-Maxwellian state (the input)
    assert stats.kstest(c_in[:, 0], "norm").pvalue < 1e-6
    for a in range(3):
        assert stats.kstest(c_out[:, a], "norm").pvalue > 1e-3
    if zeta > 0:
        assert stats.kstest(e_in, stats.gamma(0.5 * zeta).cdf).pvalue < 1e-6
        assert stats.kstest(e_out, stats.gamma(0.5 * zeta).cdf).pvalue > 1e-3
        # equipartition: internal energy per particle ζ/2 θ, translational 3/2 θ
        assert e_out.mean() == pytest.approx(0.5 * zeta, rel=0.01)
    assert (0.5 * (c_out**2).sum(axis=1)).mean() == pytest.approx(1.5, rel=0.01)


def test_redraw_depends_on_seed_and_step_only():
    rng = np.random.default_rng(2)
    v, e, cell, start = _cells([50] * 64, rng)
    results = []
    for threads, seed, step in ((1, 5, 3), (numba.config.NUMBA_NUM_THREADS, 5, 3), (1, 6, 3), (1, 5, 4)):
        numba.set_num_threads(threads)
        v1, e1 = v.copy(), e.copy()
        _redraw(v1, e1, start, 2.0, seed, step)
        results.append((v1, e1))
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    np.testing.assert_array_equal(results[0][0], results[1][0])  # bit-identical at any thread count
    np.testing.assert_array_equal(results[0][1], results[1][1])
    assert not np.any(results[0][0] == results[2][0])  # another seed, another draw
    assert not np.any(results[0][0] == results[3][0])  # another step, another draw


@numba.njit(cache=True)
def _variates(seed, n, shape):
    """n uniform, n normal and n Gamma(shape) draws of one stream."""
    state = stream(seed, 0, 0)
    u = np.empty(n)
    z = np.empty(n)
    g = np.empty(n)
    for k in range(n):
        state, u[k] = uniform(state)
        state, z[k] = normal(state)
        state, g[k] = gamma(state, shape)
    return u, z, g


@pytest.mark.parametrize("shape", [0.4, 1.0, 1.5, 4.0])
def test_streams_draw_uniform_normal_and_gamma_variates(shape):
    u, z, g = _variates(99, 50_000, shape)
    assert np.all((u > 0.0) & (u < 1.0))
    assert stats.kstest(u, "uniform").pvalue > 1e-3
    assert stats.kstest(z, "norm").pvalue > 1e-3
    assert stats.kstest(g, stats.gamma(shape).cdf).pvalue > 1e-3


def test_normal_draws_reach_the_ziggurat_tail_as_often_as_the_normal():
    z = _variates(7, 400_000, 1.0)[1]
    # beyond the base strip's edge r = 3.4426: 2 Φ(−r) = 5.76e-4 of the draws, 230 ± 15 here
    tail = np.abs(z) > 3.442619855899
    assert abs(tail.sum() - 400_000 * 2 * stats.norm.sf(3.442619855899)) < 4 * np.sqrt(230)
    assert stats.kstest(np.abs(z[tail]) - 3.442619855899, lambda t: 1 - stats.norm.sf(3.442619855899 + t)
                        / stats.norm.sf(3.442619855899)).pvalue > 1e-3
    assert abs(np.mean(z**4) - 3.0) < 0.05  # kurtosis of the normal


@pytest.mark.parametrize("dim", [1, 2])
def test_cell_sort_is_the_stable_sort_whatever_the_chunk_count(dim):
    rng = np.random.default_rng(3)
    shape = np.array([13, 7][:dim], dtype=np.int64)
    lo, spacing = np.array([-1.0, 2.0][:dim]), np.array([0.1, 0.3][:dim])
    n = 5000
    # positions inside the grid and some beyond it (they go to the nearest cell)
    x = lo + rng.uniform(-0.05, 1.05, (n, dim)) * shape * spacing
    v, e, w = rng.normal(size=(n, 3)), rng.uniform(size=n), rng.uniform(size=n)
    index = np.clip(np.floor((x - lo) / spacing).astype(int), 0, shape - 1)
    cell = index[:, 0] + (index[:, 1] * shape[0] if dim == 2 else 0)
    keep = rng.uniform(size=n) > 0.1  # the rest left the run: dropped by the sort
    order = np.flatnonzero(keep)[np.argsort(cell[keep], kind="stable")]
    for chunks in (1, 2, 3, 64):
        xs, vs, es, ws = np.empty_like(x), np.empty_like(v), np.empty_like(e), np.empty_like(w)
        start = sort_into_cells(x, v, e, w, keep, lo, spacing, shape, chunks, xs, vs, es, ws)
        kept = start[-1]
        assert kept == keep.sum()
        np.testing.assert_array_equal(xs[:kept], x[order])
        np.testing.assert_array_equal(vs[:kept], v[order])
        np.testing.assert_array_equal(es[:kept], e[order])
        np.testing.assert_array_equal(ws[:kept], w[order])  # the weights of r–z travel with their particles
        np.testing.assert_array_equal(np.diff(start), np.bincount(cell[keep], minlength=int(np.prod(shape))))
        unweighted = sort_into_cells(x, v, e, np.empty(0), keep, lo, spacing, shape, chunks, xs, vs, es, np.empty(0))
        np.testing.assert_array_equal(unweighted, start)


@pytest.mark.parametrize("f, area, x", [
    (lambda x: np.exp(-0.5 * x * x), random.NORMAL_AREA, random._NORMAL_X),
    (lambda x: np.exp(-x), random.EXPONENTIAL_AREA, random._EXP_X),
])
def test_ziggurat_layers_have_equal_areas_and_cover_the_density(f, area, x):
    layers = len(x) - 1
    # every strip i ≥ 1: x_i (f(x_{i+1}) − f(x_i)) = area, the top one closing at f(0)
    strips = x[1:layers] * (f(x[2:]) - f(x[1:layers]))
    np.testing.assert_allclose(strips, area, rtol=1e-8)
    # the base strip: the rectangle below f(r) plus the tail, ∫_r^∞ f
    from scipy.integrate import quad
    assert x[0] * f(x[1]) == pytest.approx(x[1] * f(x[1]) + quad(f, x[1], np.inf)[0], rel=1e-9)
