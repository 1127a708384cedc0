"""The fv solver's conservative cut-cell immersed boundary
(``partmesh.gridref.euler.immersed``): geometry against the exact shapes, a gas at
rest kept at rest, mass and energy conserved to round-off in a closed box
holding a blast array, and a run over one period across y equal to the
full-width run."""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import partmesh
from partmesh.cases.errors import InputError
from partmesh.cases.shape_factories import circle, square
from partmesh.gridref.euler.immersed import MIX, immersed_boundary
from partmesh.gridref.euler.state import conservative
from partmesh.gridref.euler.step import Scheme, Stepper
from partmesh.gridref.grid import bilinear_stencil, solver_grid


def test_volume_fractions_and_walls_measure_the_shapes():
    """Σ κ V is the box less the bodies' areas, Σ |B| their perimeters, and
    the wall vectors of each closed body sum to zero (closure)."""
    h = 1e-3
    grid = solver_grid(((0.0, 0.1), (0.0, 0.05)), h)
    bodies = [circle(0.03, 0.025, 0.0267), square(0.07, 0.025, 0.0267)]
    ib = immersed_boundary(grid, bodies)
    open_area = ib.volume.sum() * h * h
    solid_area = 0.1 * 0.05 - open_area
    exact = math.pi * 0.01335 ** 2 + 0.0267 ** 2
    assert solid_area == pytest.approx(exact, rel=2e-3)
    wall = ib.wall * h * h  # B per cell [m]
    perimeter = np.hypot(wall[0], wall[1]).sum()
    # the square's sides run along the grid lines (exact); the circle's staircase of apertures
    # measures its perimeter to the cut resolution
    assert perimeter == pytest.approx(2 * math.pi * 0.01335 + 4 * 0.0267, rel=2e-2)
    assert np.abs(wall.sum(axis=1)).max() < 1e-12


def test_small_cells_are_merged_into_groups_of_at_least_half_a_cell():
    scene = partmesh.scene("blast_array", arrangement="staggered", shape="triangle_left", rows=1)
    grid = solver_grid(scene.domain, 2e-3)
    ib = immersed_boundary(grid, scene.obstacles, (False, True))
    kappa = ib.volume.ravel()
    small = (kappa > 0) & (kappa < MIX)
    assert small.sum() > 20  # the rods do cut cells
    group_volume = np.bincount(ib.group, weights=kappa, minlength=kappa.size)
    assert np.all(group_volume[ib.group[small]] >= MIX)
    assert np.all(kappa[ib.group[small]] > 0)


@pytest.mark.full
def test_a_gas_at_rest_stays_at_rest_around_rods():
    """The wall vector closes every cut cell, so the walls' pressure
    balances the faces' to round-off."""
    h = 1e-3
    grid = solver_grid(((0.0, 0.1), (0.0, 0.04)), h)
    ib = immersed_boundary(grid, [circle(0.05, 0.0, 0.0267), circle(0.05, 0.04, 0.0267)], (False, True))
    shape = ib.shape
    W = (jnp.ones(shape), jnp.zeros(shape), jnp.zeros(shape), jnp.full(shape, 1e5))
    U = conservative(W, 1.4)
    stepper = Stepper(Scheme(gamma=1.4, dx=(h, h), kinds=("reflect", "reflect", "periodic", "periodic")),
                      immersed=ib, solid_state=U)
    dt = float(stepper.initial_dt(U))
    for _ in range(50):
        U, dt, _, _ = stepper(U, dt, 0.0)
    fluid = ib.fluid
    speed = np.hypot(np.asarray(U[1]), np.asarray(U[2]))[fluid]
    assert speed.max() < 1e-9 * math.sqrt(1.4e5)
    assert np.abs(np.asarray(U[0])[fluid] - 1.0).max() < 1e-12


def _closed_box(dx):
    """A staggered blast array (rods cut by the periodic sides) in a box
    closed at both ends, a high-pressure slab at its upstream end."""
    scene = partmesh.scene("blast_array", arrangement="staggered", rows=1)

    def initial(x, y, dx):
        hot = x < 0.2
        return np.where(hot, 5.0, 1.0), 0.0, 0.0, np.where(hot, 1e6, 1e5)

    sides = {**scene.boundaries, "x_lo": "reflect"}
    return dataclasses.replace(scene, boundaries=sides, initial=initial)


@pytest.mark.full
def test_a_closed_box_holding_an_array_keeps_its_mass_and_energy():
    """3 ms of a shock through a staggered array and back: mass and energy
    to round-off (a ghost-cell boundary gains 2–4 % of the mass here)."""
    ds = partmesh.run(_closed_box(4e-3), "fv", dx=4e-3, progress=False)
    assert float(ds.time[-1]) == pytest.approx(3e-3)
    assert float(ds.wall_force.max()) > 1e4  # the shock loaded the far wall
    assert ds.attrs["mass_drift"] < 1e-12
    assert ds.attrs["energy_drift"] < 1e-12


@pytest.mark.full
def test_one_period_across_y_equals_the_full_channel():
    runs = [partmesh.run(partmesh.scene("blast_array", arrangement="staggered", one_period=one, t_end=1.6e-3), "fv",
                      dx=4e-3, progress=False) for one in (True, False)]
    reduced, full = runs
    assert reduced.attrs["tiled"].startswith("one period of 0.04 m")
    np.testing.assert_array_equal(reduced.y, full.y)
    np.testing.assert_array_equal(reduced.probe_y, full.probe_y)
    np.testing.assert_array_equal(reduced.solid, full.solid)
    peak = float(np.abs(full.wall_force).max())
    assert peak > 1e4
    assert float(np.abs(reduced.wall_force - full.wall_force).max()) < 1e-9 * peak
    assert float((np.abs(reduced.rho - full.rho) / full.rho).max()) < 1e-9


def test_bilinear_stencil_wraps_around_a_periodic_axis():
    grid = solver_grid(((0.0, 1.0), (0.0, 1.0)), 0.25)  # centres 0.125 ... 0.875
    idx, w = bilinear_stencil(grid, [(0.5, 0.0)], periodic=(False, True))
    rows = idx[0] // 4
    assert set(rows.tolist()) == {0, 3}  # between the last row and the first
    np.testing.assert_allclose(w.sum(), 1.0)
    np.testing.assert_allclose(w[0][rows == 3].sum(), 0.5)


def test_a_rod_cut_by_a_periodic_side_needs_its_other_part():
    scene = partmesh.scene("blast_array", arrangement="staggered")
    half = tuple(rod for rod in scene.obstacles if rod.bounds()[3] < 0.12 + 1e-9)  # drops the part at y = W
    with pytest.raises(InputError, match=r"is cut by the periodic side y_lo .* its other part, shifted by 0.12 m"):
        partmesh.run(dataclasses.replace(scene, obstacles=half), "fv", dx=2e-3, t_end=1e-5, progress=False)


def _box(a, periodic):
    """3 × 3 neighbourhood sums over the whole grid (wrapped along periodic axes, zero beyond the others)."""
    for axis, wrap in ((0, periodic[1]), (1, periodic[0])):
        width = [(0, 0)] * a.ndim
        width[axis] = (1, 1)
        padded = jnp.pad(a, width, mode="wrap" if wrap else "constant")
        a = sum(jax.lax.slice_in_dim(padded, k, k + a.shape[axis], axis=axis) for k in range(3))
    return a


def _redistributed_everywhere(ib, U, divergence, dt):
    """Flux redistribution (Chern & Colella 1987) evaluated on every cell of the grid: the oracle."""
    kappa = jnp.asarray(ib.volume)
    around = _box(kappa, ib.periodic)
    others = around - kappa
    share_ok = others > 0.0
    out = []
    for u, D in zip(U, divergence):
        average = _box(D, ib.periodic) / jnp.where(around > 0.0, around, 1.0)
        hybrid = jnp.where(share_ok, D + (1.0 - kappa) * average, D / jnp.where(kappa > 0.0, kappa, 1.0))
        deficit = jnp.where(share_ok, (1.0 - kappa) * (D - kappa * average), 0.0)
        share = deficit / jnp.where(share_ok, others, 1.0)
        out.append(jnp.where(kappa > 0.0, u - dt * (hybrid + _box(share, ib.periodic) - share), u))
    return ib.mixed(tuple(out))


@pytest.mark.parametrize("parameters", [dict(one_period=True), dict(arrangement="staggered", shape="triangle_left"),
                                        dict(one_period=True, arrangement="staggered", shape="square")])
def test_redistribution_over_the_band_equals_it_over_every_cell_to_round_off(parameters):
    # closed slivers (κ = 0 with open faces) give shares too: random right-hand sides everywhere, solids included
    scene = partmesh.scene("blast_array", **parameters)
    grid = solver_grid(scene.domain, 2e-3)
    ib = immersed_boundary(grid, scene.obstacles, scene.periodic)
    rng = np.random.default_rng(1)
    U = tuple(jnp.asarray(rng.random(ib.shape)) for _ in range(4))
    D = [jnp.asarray(rng.normal(size=ib.shape)) for _ in range(4)]
    fast = jax.jit(lambda U, D: ib.advanced(U, D, 1e-3))(U, D)
    oracle = jax.jit(lambda U, D: _redistributed_everywhere(ib, U, D, 1e-3))(U, D)
    for a, b in zip(fast, oracle):  # (the same sums in the same order; XLA may contract one product differently)
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=1e-14, atol=0.0)
    assert ib.redistribution[2].size < 0.1 * ib.volume.size  # (the point: few cells take part)
