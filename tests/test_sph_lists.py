"""Verlet neighbour lists of gas SPH (partmesh.particle.sph.lists): lists kept while
the particles move hold every pair that interacts at the new positions
(brute force, mirror ghosts and periodic images included), and they are
kept as long as the relative motion allows, not the fastest particle."""

from types import SimpleNamespace

import numpy as np
import pytest

from partmesh.particle.sph.lists import VerletLists
from tests.test_neighbours import brute

#: a unit box with reflecting walls across x and periodic in y
BOX = SimpleNamespace(sides=("x_lo", "x_hi", "y_lo", "y_hi"), domain=((0.0, 1.0), (0.0, 1.0)),
                      boundaries={"x_lo": "reflect", "x_hi": "reflect", "y_lo": "periodic", "y_hi": "periodic"})


def lattice(spacing=0.02):
    """A square lattice filling :data:`BOX`, with its support 2.6 spacings."""
    ticks = np.arange(0.5 * spacing, 1.0, spacing)
    x = np.stack(np.meshgrid(ticks, ticks, indexing="ij"), axis=-1).reshape(-1, 2)
    return x, np.full(x.shape[0], 2.6 * spacing)


def verlet():
    return VerletLists(BOX, (0.0, 0.0), (1.0, 1.0), (False, True))


def steps_kept(velocity, H, steps=40, dt=4e-5):
    """How many steps the lists of the lattice in :data:`BOX` moving at
    ``velocity(x)`` (a field) are kept before a new search is needed."""
    x, _ = lattice()
    lists = verlet()
    lists.search(x, velocity(x), H, x.shape[0], 1.25)
    for k in range(1, steps + 1):
        moved = lists.wrapped(x + k * dt * velocity(x))
        if lists.reusable(moved, velocity(moved), H, x.shape[0]) is None:
            return k - 1
    return steps


@pytest.mark.full
def test_kept_lists_hold_every_pair_that_interacts_at_the_moved_positions():
    rng = np.random.default_rng(3)
    x, H = lattice()
    x += rng.normal(0.0, 0.002, x.shape)
    x[:, 0] = np.clip(x[:, 0], 1e-3, 1.0 - 1e-3)
    H *= rng.uniform(0.8, 1.2, H.size)
    H[:20] *= 4.0  # a few wide supports, bounded by the range of all displacements
    v = rng.normal(0.0, 0.2, x.shape)
    v[:, 0] += 0.5 * np.sin(2 * np.pi * x[:, 1])  # a shear across the periodic axis
    n = x.shape[0]
    lists = verlet()
    lists.search(x, v, H, n, 1.25)
    kept = 0
    for k in range(1, 30):
        moved = lists.wrapped(x + 1e-3 * k * v)
        moved[:, 0] = np.clip(moved[:, 0], 1e-3, 1.0 - 1e-3)
        H_now = H * (1.0 + 0.004 * k)
        reused = lists.reusable(moved, v, H_now, n)
        if reused is None:
            break
        kept += 1
        # every pair r < max(H_i, H_j) among the particles and their mirror ghosts is in the lists
        src = np.concatenate([np.arange(n), reused.src])
        hit, _ = brute(reused.x, H_now[src], (0.0, 0.0), (1.0, 1.0), (False, True))
        for i in range(n):
            assert set(np.flatnonzero(hit[i])) <= set(reused.index[reused.offsets[i]:reused.offsets[i + 1]]), i
    assert kept >= 2


def test_gas_streaming_as_a_whole_keeps_its_lists_and_shear_renews_them():
    # a uniform stream along the walls at 300 m/s moves 12 mm a step, a quarter of a support: the bound with the largest
    # displacement (|δ_i| + max |δ|) would search at the first step, but no pair comes any closer
    _, H = lattice()
    assert steps_kept(lambda x: np.tile([0.0, 300.0], (x.shape[0], 1)), H) == 40
    # a shear of 1000 /s along the walls: neighbours one support apart part at 52 m/s (2 mm a step),
    # which uses up the skin (0.25 to 0.5 H, 13 to 26 mm) within a few steps (the bound takes the range
    # over three cells, ~3 supports)
    sheared = steps_kept(lambda x: np.stack([np.zeros(x.shape[0]), 1000.0 * x[:, 0]], axis=1), H)
    assert 0 < sheared < 10


@pytest.mark.parametrize("shift", [0, 1])
def test_a_different_particle_count_or_order_forces_a_search(shift):
    x, H = lattice()
    v = np.zeros_like(x)
    lists = verlet()
    lists.search(x, v, H, x.shape[0], 1.25)
    assert lists.reusable(x, v, H, x.shape[0]) is not None
    if shift:
        assert lists.reusable(np.roll(x, 1, axis=0), v, H, x.shape[0]) is None
    else:
        assert lists.reusable(x[:-1], v[:-1], H[:-1], x.shape[0] - 1) is None
