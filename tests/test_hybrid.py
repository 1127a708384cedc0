"""Hybrid finite-volume – SPH (method ``hybrid``): its pieces and the coupled
system against conservation, exact solutions and pure SPH."""


import numpy as np
import pytest

import partmesh
from partmesh.cases.errors import InputError, SolverFailed
from partmesh.compare.metrics import field_error
from partmesh.hybrid.cells import cell_of, dilated, flagged, lattice, relaid, relative_jumps, ring, sensed_jumps
from partmesh.hybrid.exchange import cloud, deposited, interpolated, matched

SOD = partmesh.scene("sod")


def test_jumps_flag_the_cells_on_both_sides_of_a_step_and_the_buffer_around():
    rho = np.where(np.arange(40) < 20, 1.0, 0.5)
    p = np.ones(40)
    assert relative_jumps(rho, (False, False))[[18, 19, 20, 21]].tolist() == [0.0, 1.0, 1.0, 0.0]
    owned = flagged(sensed_jumps(np.stack([rho, 0 * p, p]), "rho,p", (False, False)), 0.1, 3, (False, False))
    assert np.flatnonzero(owned).tolist() == list(range(16, 24))


def test_pressure_alone_flags_the_shock_and_leaves_the_contact_to_the_grid():
    # sod at t = 0.2 in caricature: a contact (density jump, even pressure) at cell 27, a shock at 34
    rho = np.select([np.arange(40) < 27, np.arange(40) < 34], [0.43, 0.27], 0.125)
    p = np.where(np.arange(40) < 34, 0.30, 0.1)
    W = np.stack([rho, np.zeros(40), p])
    assert np.flatnonzero(flagged(sensed_jumps(W, "rho,p", (False, False)), 0.1, 1, (False, False))).tolist() == [
        25, 26, 27, 28, 32, 33, 34, 35]
    assert np.flatnonzero(flagged(sensed_jumps(W, "p", (False, False)), 0.1, 1, (False, False))).tolist() == [
        32, 33, 34, 35]


def test_the_shock_sensor_flags_a_compression_and_leaves_an_expansion_to_the_grid():
    # a blast in caricature, moving right: the shock at cell 30 (flow converging), and behind it a
    # pressure fall with the flow speeding up outwards (diverging), as in the Sedov–Taylor interior
    x = np.arange(40)
    p = np.where(x <= 30, 4.0 * 0.8 ** (30 - x), 1.0)
    u = np.where(x <= 30, 2.0 * x / 30, 0.0)
    W = np.stack([np.ones(40), u, p])
    assert np.flatnonzero(sensed_jumps(W, "p", (False, False)) > 0.2).tolist() == list(range(32))
    assert np.flatnonzero(sensed_jumps(W, "shock", (False, False)) > 0.2).tolist() == [30, 31]
    # at rest (the first step of a blast) every jump counts
    W[1] = 0.0
    assert np.array_equal(sensed_jumps(W, "shock", (False, False)), sensed_jumps(W, "p", (False, False)))


def test_jumps_wrap_around_periodic_axes_only():
    rho = np.ones((4, 10))
    rho[:, 0] = 2.0  # a jump between the last column and the first across the periodic side
    periodic = relative_jumps(rho, (True, False))
    closed = relative_jumps(rho, (False, False))
    assert periodic[0, -1] == 1.0 and closed[0, -1] == 0.0
    assert periodic[0, 1] == closed[0, 1] == 1.0


def test_ring_surrounds_the_region_with_diagonals_and_wraps():
    inner = np.zeros((7, 7), bool)
    inner[3, 3] = True
    # a reach of k cells from the centre: the k-th square around it, less the centre
    assert ring(inner, 2 * inner, (False, False)).sum() == 8
    assert ring(inner, 3 * inner, (False, False)).sum() == 24
    # each cell reaches as far as its own reach: a wide one at the left end of a strip, narrow elsewhere
    strip = np.zeros((9, 12), bool)
    strip[4, 2:10] = True
    reach = np.where(strip, 2, 0)
    reach[4, 2] = 4
    around = ring(strip, reach, (False, False))
    assert around[4, 0] and around[1, 2] and around[1, 3] and around[1, 4]  # 3 cells from the wide one
    assert not around[1, 6] and around[3, 6] and around[5, 6] and around[4, 10] and not around[4, 11]
    assert np.array_equal(ring(strip, 2 * strip, (False, False)), dilated(strip, 1, (False, False)) & ~strip)
    # and wraps around a periodic axis
    assert ring(strip, reach, (True, False))[4, 11]
    edge = np.zeros((5, 6), bool)
    edge[2, 0] = True
    grown = dilated(edge, 1, (True, False))
    assert grown[2, 5] and grown[1, 5] and not grown[2, 2]


def test_the_injection_lattice_fills_each_cell_evenly():
    lo, dx, shape = np.array([0.0, -1.0]), np.array([0.1, 0.1]), (8, 5)
    cells = np.array([0, 9, 39])
    x, owner = lattice(cells, lo, dx, shape, 4)
    assert x.shape == (48, 2)
    assert np.array_equal(cell_of(x, lo, dx, shape), owner)
    for c in cells:  # a 4×4 lattice centred in its cell
        pts = x[owner == c]
        corner = lo + dx * np.array([c % 8, c // 8])
        assert np.allclose(np.sort(np.unique(np.round((pts[:, 0] - corner[0]) / 0.025, 9))), [0.5, 1.5, 2.5, 3.5])
        assert np.allclose(pts.mean(axis=0), corner + 0.05)


def _particles(n, dim, seed=0):
    from partmesh.particle.sph.scheme import Particles

    rng = np.random.default_rng(seed)
    return Particles(x=rng.uniform(0.0, 1.0, (n, dim)), v=rng.normal(0.0, 1.0, (n, dim)), u=rng.uniform(1.0, 2.0, n),
                     m=rng.uniform(0.5, 1.5, n), H=np.full(n, 0.1), alpha=np.zeros(n), alpha_u=np.zeros(n),
                     rho=np.ones(n), products=np.zeros(n, bool))


def test_cells_are_relaid_when_thinned_out_or_holding_an_expanded_heavy_particle():
    # four cells of 16 lattice points (volume 1): lattice mass at density rho is rho / 16
    full = np.repeat([0, 1, 2], 16)  # cells 0-2 full, cell 3 holds 3 particles (< 4)
    cell = np.concatenate([full, [3, 3, 3]])
    m = np.full(cell.size, 2.0 / 16)
    dens = np.full(cell.size, 2.0)
    assert relaid(cell, m, dens, 4, 16, 1.0, 4.0).tolist() == [False, False, False, True]
    # a particle of cell 1 that has expanded to a fifth of its density: 5 lattice masses there
    dens[20] = 0.4
    assert relaid(cell, m, dens, 4, 16, 1.0, 4.0).tolist() == [False, True, False, True]
    # ... to a third: 3 lattice masses, below the limit of 4
    dens[20] = 2.0 / 3.0
    assert relaid(cell, m, dens, 4, 16, 1.0, 4.0).tolist() == [False, False, False, True]


def test_deposit_puts_the_owned_part_of_every_cloud_on_the_grid():
    import partmesh.gridref.grid as gg

    grid = gg.solver_grid(((0.0, 1.0), (0.0, 1.0)), 0.1)
    P = _particles(500, 2)
    owned = np.zeros(100, bool)
    owned[[12, 13, 14, 22, 23, 24, 55]] = True
    weights = cloud(gg.bilinear_stencil(grid, P.x), owned)
    D = deposited(weights, P.m, P.v, P.u, 100, 0.01)
    share = weights[1].sum(axis=1)
    assert np.all(D[:, ~owned] == 0.0)
    expected = [P.m @ share, *((P.m * share) @ P.v), (P.m * share) @ (P.u + 0.5 * np.sum(P.v ** 2, axis=1))]
    assert np.allclose(D.sum(axis=1) * 0.01, expected, rtol=1e-13)
    everywhere = deposited(cloud(gg.bilinear_stencil(grid, P.x), np.ones(100, bool)), P.m, P.v, P.u, 100, 0.01)
    assert everywhere[0].sum() * 0.01 == pytest.approx(P.m.sum(), rel=1e-14)


def test_matching_reaches_the_totals_to_round_off_and_keeps_energies_positive():
    P = _particles(300, 2, seed=1)
    share = np.random.default_rng(2).uniform(0.3, 1.0, 300)
    held = lambda Q: np.array([Q.m @ share, *((Q.m * share) @ Q.v),  # noqa: E731
                               (Q.m * share) @ (Q.u + 0.5 * np.sum(Q.v ** 2, axis=1))])
    target = held(P) * np.array([1.003, 1.0, 1.0, 0.998]) + np.array([0.0, 0.5, -0.2, 0.0])
    Q = matched(P, share, target)
    assert np.allclose(held(Q), target, rtol=1e-13, atol=1e-12)
    assert np.all(Q.u > 0) and np.allclose(Q.m / P.m, Q.m[0] / P.m[0])
    with pytest.raises(FloatingPointError, match="internal energy"):
        matched(P, share, target * np.array([1.0, 1.0, 1.0, 1e-3]))


def test_matching_leaves_the_momentum_across_a_wall_to_the_particles():
    # a blast in a corner: the walls push the grid's cells and the particles differently,
    # so a common shift along a walled axis would move every particle by the difference
    P = _particles(200, 2, seed=4)
    share = np.ones(200)
    target = np.array([P.m.sum(), *(P.m @ P.v + np.array([3.0, -2.0])), P.m @ (P.u + 0.5 * np.sum(P.v ** 2, axis=1))])
    Q = matched(P, share, target, axes=np.array([True, False]))
    assert np.allclose(Q.v[:, 1], P.v[:, 1], rtol=0, atol=1e-15)
    assert Q.m @ Q.v[:, 0] == pytest.approx(target[1], rel=1e-13)
    assert Q.m @ (Q.u + 0.5 * np.sum(Q.v ** 2, axis=1)) == pytest.approx(target[-1], rel=1e-13)


def test_interpolation_is_exact_for_a_linear_field():
    import partmesh.gridref.grid as gg

    grid = gg.solver_grid(((0.0, 1.0), (0.0, 2.0)), 0.1)
    X, Y = gg.mesh(grid)
    W = np.stack([1.0 + 2.0 * X - 3.0 * Y, 0.5 * X])
    points = np.random.default_rng(3).uniform([0.05, 0.05], [0.95, 1.95], (50, 2))
    values = interpolated(W, gg.bilinear_stencil(grid, points))
    assert np.allclose(values[0], 1.0 + 2.0 * points[:, 0] - 3.0 * points[:, 1])
    assert np.allclose(values[1], 0.5 * points[:, 0])


@pytest.fixture(scope="module")
def sedov_hybrid():
    return partmesh.run(partmesh.scene("sedov", n_out=128, t_end=0.1), "hybrid", progress=False)


def test_hybrid_conserves_mass_and_energy_in_a_closed_box(sedov_hybrid):
    ds = sedov_hybrid
    assert ds.attrs["mass_drift"] < 1e-12 and ds.attrs["energy_drift"] < 1e-12
    assert ds.attrs["particles_max"] > 0 and ds.attrs["sph_substeps"] > ds.attrs["n_steps"]
    # the fluid particles are counted apart from the boundary ring around them
    assert 0 < ds.attrs["fluid_particles_max"] < ds.attrs["particles_max"]
    assert 0 < ds.attrs["fluid_particle_steps"] < ds.attrs["particle_steps"]


def test_hybrid_sub_steps_reuse_the_neighbour_lists(sedov_hybrid):
    # roles change only between grid steps: a search at each, and one whenever the particles
    # have moved through the lists' skin, not one per sub-step
    ds = sedov_hybrid
    assert ds.attrs["neighbour_searches"] < 0.6 * ds.attrs["sph_substeps"]


def test_hybrid_sedov_shock_radius_follows_sedov_taylor(sedov_hybrid):
    ds = sedov_hybrid
    exact = partmesh.scene("sedov", n_out=128, t_end=0.1).exact(ds.time.values[-1:])
    r = np.hypot(*np.meshgrid(ds.x.values, ds.y.values))
    rho = ds.rho.isel(time=-1).values
    rho_exact = exact.rho.isel(time=-1).values
    # radius of the density peak, averaged over angle, against the exact shock radius
    peak = np.average(r, weights=np.where(rho > 0.5 * rho.max(), rho, 0.0))
    peak_exact = np.average(r, weights=np.where(rho_exact > 0.5 * rho_exact.max(), rho_exact, 0.0))
    assert abs(peak / peak_exact - 1.0) < 0.05


@pytest.mark.full
def test_hybrid_sod_density_error_is_within_a_fifth_of_pure_sph_at_the_same_spacing():
    dx = 1 / 800
    errors = {}
    for method in ("hybrid", "sph"):
        ds = partmesh.run(SOD, method, dx=dx, progress=False)
        errors[method] = field_error(ds.rho.isel(time=-1), SOD.exact(ds.time.values).rho.isel(time=-1))
    assert errors["hybrid"] <= 1.2 * errors["sph"]
    assert errors["hybrid"] < 5e-3


@pytest.mark.full
def test_hybrid_sod_holds_particles_only_near_the_waves():
    ds = partmesh.run(SOD, "hybrid", dx=1 / 800, progress=False)
    # the grid has 200 cells of 4 particles: the waves span about 0.6 of the tube at t = 0.2
    assert ds.attrs["particles_max"] < 0.75 * 800
    assert ds.attrs["dx"] == pytest.approx(1 / 800) and ds.attrs["fv_cells"] == 200


@pytest.mark.parametrize("settings, words", [
    (dict(beta=0.3), "beta must be 1/k"),
    (dict(threshold=0.0), "threshold"),
    (dict(buffer=-1), "buffer"),
    (dict(sensor="rho"), "sensor"),
    (dict(cfl_sph=1.5), "cfl_sph"),
    (dict(smoothing=2), "no setting 'smoothing'"),
])
def test_hybrid_refuses_bad_settings_in_one_sentence(settings, words):
    with pytest.raises(InputError, match=words):
        partmesh.run(SOD, "hybrid", progress=False, **settings)


def test_a_collapsed_particle_sub_step_stops_the_run_with_what_it_computed():
    # a Courant number that is in range but leaves the sub-steps too short to end the run: the grid's own step
    # is fine, so the particles' sub-step has to be held to the loop's floor (DT_FLOOR t_end) too
    with pytest.raises(SolverFailed, match=r"^hybrid failed at t = .*: the particles' sub-step collapsed to "
                                           r"[0-9.e-]+ s at t = 0 s\.$") as failure:
        partmesh.run("sod", "hybrid", dx=1 / 40, t_end=0.01, cfl_sph=1e-300, progress=False)
    assert failure.value.partial is not None and failure.value.partial.attrs["status"] == "failed"


def test_hybrid_refuses_scenes_with_obstacles():
    with pytest.raises(InputError, match="without obstacles"):
        partmesh.run(partmesh.scene("blast_array", one_period=True), "hybrid", progress=False)


@pytest.mark.full
def test_settings_given_as_text_run_as_their_values():
    # the CLI passes --option eta=4 as the text '4': the particles must see the number
    as_text = partmesh.run("sod", "hybrid", dx=5e-3, eta="4", alpha_max="2.5", kernel="wendland_c6", progress=False)
    as_numbers = partmesh.run("sod", "hybrid", dx=5e-3, eta=4.0, alpha_max=2.5, progress=False)
    np.testing.assert_array_equal(as_text["rho"].values, as_numbers["rho"].values)
