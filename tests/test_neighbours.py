"""Cell-linked-list neighbour search (partmesh.particle.neighbours) against brute
force: variable H, periodic axes (pairs across the boundary), particles
outside the box on walled axes, symmetry, the dx sign convention, r = |dx|,
determinism; and the cell sort."""

from __future__ import annotations

import numba
import numpy as np
import pytest

from partmesh.cases.errors import InputError
from partmesh.particle.cell_grid import nearby_maximum, sort_order
from partmesh.particle.neighbours import neighbour_lists, neighbours, renumbered


def brute(x, H, lo, hi, periodic):
    """All pairs r_ij < max(H_i, H_j), i ≠ j, minimum image on periodic axes."""
    x = np.asarray(x, float).reshape(len(x), -1)
    d = x[:, None, :] - x[None, :, :]
    L = np.asarray(hi, float) - np.asarray(lo, float)
    for a, per in enumerate(periodic):
        if per:
            d[..., a] -= L[a] * np.round(d[..., a] / L[a])
    r = np.sqrt((d**2).sum(-1))
    hit = r < np.maximum(H[:, None], H[None, :])
    np.fill_diagonal(hit, False)
    return hit, d


def check_against_brute(x, H, lo, hi, periodic, **kw):
    offsets, index, dx, r = neighbours(x, H, lo, hi, periodic, **kw)
    n = len(x)
    hit, d = brute(x, H, lo, hi, periodic)
    assert offsets.shape == (n + 1,) and offsets[0] == 0 and np.all(np.diff(offsets) >= 0)
    assert index.dtype == np.int32 and offsets.dtype == np.int64
    assert dx.shape == (len(index), np.asarray(x).reshape(n, -1).shape[1])
    assert offsets[-1] == hit.sum()
    for i in range(n):
        j = index[offsets[i]:offsets[i + 1]]
        assert np.array_equal(np.sort(j), np.nonzero(hit[i])[0]), i
        np.testing.assert_allclose(dx[offsets[i]:offsets[i + 1]], d[i, j], rtol=0, atol=1e-12)
    np.testing.assert_allclose(r, np.linalg.norm(dx, axis=1), rtol=1e-15, atol=0)
    return offsets, index, dx, r


def scattered_with_wide_supports(seed, dim, n, sides, wide_fraction, widest):
    """``(lo, hi, x, H, wide)``: ``n`` random positions in a box of ``sides``
    and supports of 3–5 % of a side (times ``dim``), of which a fraction
    ``wide_fraction`` (flagged in ``wide``) is widened 2 to ``widest`` times
    (capped at 0.5): a blast's rarefied core among the bulk."""
    rng = np.random.default_rng(seed)
    lo, hi = np.zeros(dim), np.array(sides[:dim])
    x = lo + rng.random((n, dim)) * (hi - lo)
    H = rng.uniform(0.03, 0.05, n) * dim
    wide = rng.random(n) < wide_fraction
    H[wide] *= rng.uniform(2.0, widest, wide.sum())
    return lo, hi, x, np.minimum(H, 0.5), wide


CONFIGS = [
    (1, (False,)),
    (1, (True,)),
    (2, (False, False)),
    (2, (True, True)),
    (2, (True, False)),
    (2, (False, True)),
    (3, (False, False, False)),
    (3, (True, True, True)),
    (3, (False, True, False)),
]


@pytest.mark.parametrize("dim, periodic", CONFIGS)
@pytest.mark.parametrize("reach", [1, 2, 3])
def test_matches_brute_force(dim, periodic, reach):
    rng = np.random.default_rng(10 * dim + sum(periodic) + 100 * reach)
    n = {1: 300, 2: 500, 3: 600}[dim]
    lo = np.array([-0.5, 0.0, 1.0][:dim])
    hi = lo + np.array([1.0, 1.7, 1.3][:dim])
    x = lo + rng.random((n, dim)) * (hi - lo)
    # walled axes: some boundary/ghost particles outside the box
    for a, per in enumerate(periodic):
        if not per:
            out = rng.random(n) < 0.15
            x[out, a] = np.where(rng.random(out.sum()) < 0.5, lo[a] - 0.2 * rng.random(out.sum()),
                                 hi[a] + 0.2 * rng.random(out.sum()))
    H = rng.uniform(0.04, {1: 0.15, 2: 0.2, 3: 0.3}[dim], n)
    check_against_brute(x, H, lo, hi, periodic, reach=reach)


@pytest.mark.parametrize("dim, periodic", CONFIGS)
@pytest.mark.parametrize("sort_lists", [False, True])
def test_a_few_wide_particles_scan_stencils_of_their_own(dim, periodic, sort_lists):
    """Supports spread over a factor 8 (a blast's rarefied core): the cells are
    sized for the bulk, the widest particles search further, and the pairs
    only they reach are added to the narrow particles' lists."""
    n = {1: 400, 2: 800, 3: 900}[dim]
    lo, hi, x, H, _ = scattered_with_wide_supports(7 * dim + sum(periodic), dim, n, [1.0, 1.3, 1.1], 0.04, 8.0)
    offsets, index, _, _ = check_against_brute(x, H, lo, hi, periodic, sort_lists=sort_lists)
    if sort_lists:
        assert all(np.all(np.diff(index[offsets[i]:offsets[i + 1]]) > 0) for i in range(n))


def test_periodic_positions_outside_the_box_are_wrapped():
    rng = np.random.default_rng(1)
    x = rng.uniform(-1.0, 2.0, (400, 2))  # up to one period outside [0, 1)
    H = rng.uniform(0.05, 0.15, 400)
    check_against_brute(x, H, [0, 0], [1, 1], (True, True))


def test_pairs_across_the_periodic_boundary_and_dx_sign():
    x = np.array([[0.01, 0.5], [0.99, 0.5], [0.5, 0.975], [0.5, 0.02]])
    H = np.full(4, 0.05)
    offsets, index, dx, r = neighbours(x, H, [0, 0], [1, 1], (True, True))
    lists = {i: list(index[offsets[i]:offsets[i + 1]]) for i in range(4)}
    assert lists == {0: [1], 1: [0], 2: [3], 3: [2]}
    # dx = x_i − x_j with the minimum image: 0.01 − 0.99 → +0.02
    np.testing.assert_allclose(dx[offsets[0]], [0.02, 0.0], atol=1e-15)
    np.testing.assert_allclose(dx[offsets[1]], [-0.02, 0.0], atol=1e-15)
    np.testing.assert_allclose(dx[offsets[2]], [0.0, -0.045], atol=1e-15)
    np.testing.assert_allclose(r, [0.02, 0.02, 0.045, 0.045], atol=1e-15)
    # the same pair on a walled axis is not a pair
    offsets, index, _, _ = neighbours(x, H, [0, 0], [1, 1], (False, True))
    assert list(index[offsets[0]:offsets[1]]) == []


def test_dx_sign_convention_and_cutoff_is_strict():
    x = np.array([[0.0], [0.3], [0.5]])
    H = np.array([0.3, 0.1, 0.1])
    offsets, _, _, _ = neighbours(x, H, [0.0], [1.0], False, sort_lists=True)
    # r_01 = 0.3 is not < max(0.3, 0.1); r_12 = 0.2 is not < 0.1
    assert offsets.tolist() == [0, 0, 0, 0]
    H = np.array([0.31, 0.1, 0.21])
    offsets, index, dx, _r = neighbours(x, H, [0.0], [1.0], False, sort_lists=True)
    assert index.tolist() == [1, 0, 2, 1]
    np.testing.assert_allclose(dx[:, 0], [-0.3, 0.3, -0.2, 0.2], atol=1e-15)


def test_lists_are_symmetric_and_antisymmetric_in_dx():
    rng = np.random.default_rng(7)
    x = rng.random((2000, 2))
    H = rng.uniform(0.01, 0.06, 2000)
    offsets, index, dx, r = neighbours(x, H, [0, 0], [1, 1], (True, False))
    i = np.repeat(np.arange(2000), np.diff(offsets))
    pairs = {(a, b): k for k, (a, b) in enumerate(zip(i.tolist(), index.tolist()))}
    assert all((b, a) in pairs for (a, b) in pairs)
    back = np.array([pairs[(b, a)] for (a, b) in zip(i.tolist(), index.tolist())])
    np.testing.assert_array_equal(dx[back], -dx)
    np.testing.assert_array_equal(r[back], r)
    assert not np.any(index == i)


def test_deterministic_order_independent_of_threads():
    rng = np.random.default_rng(2)
    x = rng.random((3000, 2))
    H = rng.uniform(0.02, 0.05, 3000)
    first = neighbours(x, H, [0, 0], [1, 1], (True, True))
    old = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        single = neighbours(x, H, [0, 0], [1, 1], (True, True))
    finally:
        numba.set_num_threads(old)
    for a, b in zip(first, single):
        np.testing.assert_array_equal(a, b)
    offsets, index, dx, _r = neighbours(x, H, [0, 0], [1, 1], (True, True), sort_lists=True)
    np.testing.assert_array_equal(offsets, first[0])
    for i in range(0, 3000, 7):
        seg = slice(offsets[i], offsets[i + 1])
        assert np.all(np.diff(index[seg]) > 0)
        perm = np.argsort(first[1][seg])
        np.testing.assert_array_equal(index[seg], first[1][seg][perm])
        np.testing.assert_array_equal(dx[seg], first[2][seg][perm])


def test_lattice_neighbour_count():
    """A periodic 2D lattice with H = 4.2Δx (clear of ties at r = H): every
    particle sees the lattice points with 0 < |k| ≤ √17, 56 of them."""
    n = 40
    g = (np.arange(n) + 0.5) / n
    X, Y = np.meshgrid(g, g)
    x = np.column_stack([X.ravel(), Y.ravel()])
    H = np.full(n * n, 4.2 / n)
    offsets, _, _, _ = neighbours(x, H, [0, 0], [1, 1], (True, True))
    k = np.arange(-4, 5)
    expected = int(((k[:, None] ** 2 + k[None, :] ** 2) <= 17).sum() - 1)
    assert expected == 56
    assert np.all(np.diff(offsets) == expected)


def test_small_periodic_boxes_and_edge_cases():
    rng = np.random.default_rng(4)
    # a period only a few cells long, with H at the limit of half the period
    x = rng.random((60, 2)) * [1.0, 0.3]
    H = np.full(60, 0.15)
    for reach in (1, 2, 4):
        check_against_brute(x, H, [0, 0], [1, 0.3], (True, True), reach=reach)
    # empty and single-particle inputs
    off, idx, dx, r = neighbours(np.zeros((0, 2)), np.zeros(0), [0, 0], [1, 1], False)
    assert off.tolist() == [0] and idx.size == 0 and dx.shape == (0, 2)
    off, idx, dx, r = neighbours([[0.5, 0.5]], [0.1], [0, 0], [1, 1], True)
    assert off.tolist() == [0, 0]
    # a 1D array of positions and a scalar H
    check_against_brute(rng.random(100), np.full(100, 0.05), [0.0], [1.0], (True,))
    off2 = neighbours(rng.random(100), 0.05, 0.0, 1.0, True)[0]
    assert off2.shape == (101,)
    # a stray particle very far away does not blow up the cell grid
    x = rng.random((300, 2))
    x[0] = [1e9, -1e9]
    check_against_brute(x, rng.uniform(0.02, 0.08, 300), [0, 0], [1, 1], (False, False))
    # coincident particles are neighbours of each other (r = 0)
    x = np.array([[0.2, 0.2], [0.2, 0.2], [0.9, 0.9]])
    off, idx, dx, r = neighbours(x, np.full(3, 0.1), [0, 0], [1, 1], False)
    assert idx.tolist() == [1, 0] and r.tolist() == [0.0, 0.0]


def test_sort_order_is_a_cell_ordering():
    rng = np.random.default_rng(8)
    x = rng.uniform(-0.1, 1.1, (5000, 2))
    cs = 0.05
    order = sort_order(x, [0, 0], [1, 1], cs)
    assert np.array_equal(np.sort(order), np.arange(5000))
    xs = x[order]
    # cells (of width ≥ cs on the bounding box) are visited row by row, x fastest
    lo = x.min(0)
    ncell = np.floor((x.max(0) - lo) / (cs * (1 + 1e-9))).astype(int)
    width = (x.max(0) - lo) / ncell
    c = np.minimum(np.floor((xs - lo) / width).astype(int), ncell - 1)
    cid = c[:, 1] * ncell[0] + c[:, 0]
    assert np.all(np.diff(cid) >= 0)
    # stable: within a cell, original order
    same = np.diff(cid) == 0
    assert np.all(np.diff(order)[same] > 0)
    # the neighbour lists of the re-sorted particles are the re-labelled lists
    H = np.full(5000, 0.03)
    o1, i1, _, _ = neighbours(x, H, [0, 0], [1, 1], False, sort_lists=True)
    o2, i2, _, _ = neighbours(xs, H, [0, 0], [1, 1], False, sort_lists=True)
    inv = np.empty_like(order)
    inv[order] = np.arange(5000)
    for k in range(0, 5000, 11):
        i = order[k]
        assert np.array_equal(np.sort(order[i2[o2[k]:o2[k + 1]]]), i1[o1[i]:o1[i + 1]])


@pytest.mark.parametrize("dim, periodic", CONFIGS)
@pytest.mark.parametrize("sort_lists", [False, True])
def test_lists_for_the_first_rows_only_hold_all_their_pairs(dim, periodic, sort_lists):
    """rows=k: the first k particles get every pair (wide particles among
    the rest included: their pairs reach the rows' lists), the rest none."""
    n = {1: 300, 2: 600, 3: 700}[dim]
    lo, hi, x, H, wide = scattered_with_wide_supports(3 * dim + sum(periodic), dim, n, [1.0, 1.2, 1.1], 0.05, 6.0)
    rows = n // 3
    assert wide[:rows].any() and wide[rows:].any()
    offsets, index = neighbour_lists(x, H, lo, hi, periodic, sort_lists=sort_lists, rows=rows)
    hit, _ = brute(x, H, lo, hi, periodic)
    assert offsets.shape == (n + 1,) and offsets[-1] == hit[:rows].sum()
    assert np.all(offsets[rows:] == offsets[rows])
    for i in range(rows):
        j = index[offsets[i]:offsets[i + 1]]
        assert np.array_equal(j if sort_lists else np.sort(j), np.nonzero(hit[i])[0]), i


def test_bad_input_is_refused():
    x = np.random.default_rng(0).random((10, 2))
    H = np.full(10, 0.1)
    cases = [
        ((x, -H, [0, 0], [1, 1], False), "H"),
        ((x, np.full(9, 0.1), [0, 0], [1, 1], False), "H"),
        ((x, H, [0, 0], [1, 0], False), "hi"),
        ((x, H, [0, 0, 0], [1, 1, 1], False), "lo"),
        ((x, H, [0, 0], [1, 1], (True, True, False)), "periodic"),
        ((x, np.full(10, 0.6), [0, 0], [1, 1], (True, False)), "H"),
        ((np.full((10, 2), np.nan), H, [0, 0], [1, 1], False), "x"),
        ((np.zeros((10, 4)), H, [0, 0], [1, 1], False), "x"),
    ]
    for args, word in cases:
        with pytest.raises(InputError, match=word) as err:
            neighbours(*args)
        assert "\n" not in str(err.value)
    with pytest.raises(InputError, match="reach"):
        neighbours(x, H, [0, 0], [1, 1], False, reach=0)
    with pytest.raises(InputError, match="rows"):
        neighbours(x, H, [0, 0], [1, 1], False, rows=11)
    with pytest.raises(InputError, match="cell_size"):
        sort_order(x, [0, 0], [1, 1], 0.0)


def test_renumbered_lists_hold_the_same_pairs_under_the_new_ids():
    rng = np.random.default_rng(11)
    x = rng.uniform(0.0, 1.0, (400, 2))
    H = rng.uniform(0.05, 0.1, 400)
    offsets, index = neighbour_lists(x, H, np.zeros(2), np.ones(2), (True, False))
    order = rng.permutation(400)
    new_offsets, new_index = renumbered(offsets, index, order)
    # the lists of the permuted particles, searched afresh, hold the same sets
    want_offsets, want_index = neighbour_lists(x[order], H[order], np.zeros(2), np.ones(2), (True, False))
    for k in range(400):
        got = np.sort(new_index[new_offsets[k]:new_offsets[k + 1]])
        want = np.sort(want_index[want_offsets[k]:want_offsets[k + 1]])
        np.testing.assert_array_equal(got, want)
    with pytest.raises(InputError, match="permutation"):
        renumbered(offsets, index, np.zeros(400, dtype=int))


@pytest.mark.parametrize("dim, periodic", CONFIGS)
def test_nearby_maximum_bounds_the_maximum_within_the_distance(dim, periodic):
    # random values, one column and two; some points outside a walled box (mirror ghosts): the bound
    # must hold for every point and be tight enough to be useful: below the global maximum for most
    rng = np.random.default_rng(7)
    lo, hi = np.zeros(dim), np.ones(dim)
    x = rng.uniform(-0.2, 1.2, (400, dim))
    for a, per in enumerate(periodic):
        if per:
            x[:, a] = rng.random(400)
    values = rng.random((400, 2)) ** 8 - 0.5
    distance = 0.12
    hit, d = brute(x, np.full(400, distance), lo, hi, periodic)
    np.fill_diagonal(hit, True)
    exact = np.stack([np.where(hit, v[None, :], -np.inf).max(axis=1) for v in values.T], axis=1)
    bound = nearby_maximum(x, values, lo, hi, periodic, distance)
    assert bound.shape == values.shape and np.all(bound >= exact)
    assert np.array_equal(nearby_maximum(x, values[:, 1], lo, hi, periodic, distance), bound[:, 1])
    assert np.mean(bound < values.max(axis=0)) > 0.5
