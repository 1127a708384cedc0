"""DSMC free flight and the box-scene solver: exact specular reflection,
periodic wrap and removal at open sides; a closed box keeps its particles
and its energy to round-off; sod against the exact solution."""

import math

import numpy as np
import pytest

import partmesh
from partmesh.compare.metrics import field_error
from partmesh.particle.dsmc.move import OPEN, PERIODIC, REFLECT, free_flight
from partmesh.particle.dsmc.solve import landing_step


def test_specular_reflection_folds_the_path_back_and_counts_the_momentum():
    # 1D box [0, 1], reflecting both ends: a particle flying 3.3 box lengths
    # ends where the path folded into the box puts it, having bounced 3 times
    x = np.array([[0.2], [0.5], [0.9]])
    v = np.array([[3.3, 0.1, 0.0], [-0.4, 0.0, 2.0], [0.05, 0.0, 0.0]])
    gone, delivered = free_flight(x, v, 1.0, np.zeros(1), np.ones(1), np.array([REFLECT, REFLECT]))
    # 0.2 + 3.3 = 3.5 -> folded: 3.5 - 2 = 1.5 -> 2 - 1.5 = 0.5, travelling backwards after 3 bounces
    np.testing.assert_allclose(x[:, 0], [0.5, 0.1, 0.95])
    np.testing.assert_allclose(v[:, 0], [-3.3, -0.4, 0.05])
    np.testing.assert_array_equal(v[:, 1:], [[0.1, 0.0], [0.0, 2.0], [0.0, 0.0]])
    assert not gone.any()
    # bounces: at x = 1 twice and at x = 0 once, 2·3.3 each; the others do not reach a wall
    np.testing.assert_allclose(delivered, [2 * 3.3, 4 * 3.3])


def test_periodic_wrap_and_open_sides_in_2d():
    x = np.array([[0.9, 0.5], [0.1, 0.95], [0.5, 0.5]])
    v = np.array([[0.3, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, -0.6, 0.0]])
    sides = np.array([PERIODIC, PERIODIC, OPEN, OPEN])
    gone, delivered = free_flight(x, v, 1.0, np.zeros(2), np.ones(2), sides)
    np.testing.assert_allclose(x[0], [0.2, 0.5])  # wrapped in x
    np.testing.assert_array_equal(gone, [False, True, True])  # out through y_hi and y_lo
    np.testing.assert_array_equal(delivered, np.zeros(4))  # no wall was hit


@pytest.mark.parametrize("profile", ["uniform", "linear"])
def test_closed_box_keeps_every_particle_and_the_energy_to_round_off(profile):
    # Sedov in its reflecting box: specular walls and the redraw conserve energy exactly
    scene = partmesh.scene("sedov", n_out=32, t_end=0.08)
    ds = partmesh.run(scene, "dsmc", dx=2.0 / 32, ppc=20, profile=profile, progress=False)
    volume = 4.0 / 32**2
    mass = (ds["rho"] * volume).sum(dim=("x", "y"))
    assert float(np.abs(mass / mass[0] - 1).max()) < 1e-14
    rho, u, v, e = (ds[k] for k in ("rho", "u", "v", "e"))
    energy = ((rho * (e + 0.5 * (u**2 + v**2))).fillna(0.0) * volume).sum(dim=("x", "y"))
    assert ds.attrs["n_steps"] > 10
    assert float(np.abs(energy / energy[0] - 1).max()) < 1e-12


def test_sod_density_near_exact_at_a_coarse_resolution():
    # 100 cells, 100 particles per cell on the low-density side, moments over
    # 20 steps: measured L1(rho) 0.034-0.035 over seeds 0, 1, 2 (scatter and the
    # dissipation of the cell size); a collisionless gas (no redraw) is far off
    scene = partmesh.scene("sod")
    ds = partmesh.run(scene, "dsmc", dx=1 / 100, ppc=100, window=20, progress=False)
    exact = scene.exact(ds.time.values)
    assert field_error(ds["rho"].isel(time=-1), exact["rho"].isel(time=-1)) < 0.05


@pytest.mark.full
def test_sod_redrawn_about_linear_profiles_is_closer_to_exact_than_about_cell_means():
    # 100 cells, 3000 particles per cell on the low-density side (the scatter small beside the dissipation),
    # moments over 20 steps; L1(rho) measured over seeds 1, 2, 3: uniform 0.0288 / 0.0284 / 0.0278,
    # linear 0.0236 / 0.0230 / 0.0229 (0.0244 / 0.0243 / 0.0238 with minmod-limited slopes)
    scene = partmesh.scene("sod", nx_out=100)
    errors = {}
    for profile in ("uniform", "linear"):
        ds = partmesh.run(scene, "dsmc", dx=1 / 100, ppc=3000, window=20, seed=1, profile=profile, progress=False)
        exact = scene.exact(ds.time.values)
        errors[profile] = field_error(ds["rho"].isel(time=-1), exact["rho"].isel(time=-1))
    assert errors["linear"] < 0.9 * errors["uniform"]
    assert errors["linear"] < 0.026


@pytest.mark.full
@pytest.mark.parametrize("collisions", [{}, {"collisions": "larsen-borgnakke", "mean_free_path": 2.5e-3}])
def test_same_seed_same_run_at_any_thread_count_other_seed_other_run(collisions):
    import numba

    scene = partmesh.scene("shock_reflection", Ms=2.0, dim=2)  # inflow reservoir, reflecting end wall
    runs = []
    for seed, threads in ((3, numba.config.NUMBA_NUM_THREADS), (3, 1), (4, numba.config.NUMBA_NUM_THREADS)):
        numba.set_num_threads(threads)
        runs.append(partmesh.run(scene, "dsmc", dx=5e-3, ppc=10, seed=seed, t_end=5e-5, progress=False, **collisions))
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    a, b, c = runs
    for field in ("rho", "u", "v", "p"):
        np.testing.assert_array_equal(a[field].values, b[field].values)
    assert a.attrs["n_elements"] == b.attrs["n_elements"]
    assert not np.array_equal(a["rho"].values, c["rho"].values)
    assert (a.attrs["collisions"] > 0) == bool(collisions)


def test_obstacle_reflection_is_specular_and_leaves_no_particle_inside():
    from partmesh.cases.shape_factories import circle, square
    from partmesh.particle.dsmc.walls import fly_past_obstacles, obstacle_polygons, push_out_of_obstacles

    body = square(0.5, 0.5, 0.2)  # the solid [0.4, 0.6]²
    seg, nrm, start, bbox = obstacle_polygons([body], 0.01)
    # head-on into the left face, obliquely into the top face, and a miss
    x = np.array([[0.3, 0.5], [0.45, 0.7], [0.3, 0.9]])
    v = np.array([[1.0, 0.0, 0.2], [0.1, -1.0, 0.0], [1.0, 0.0, 0.0]])
    bounces = fly_past_obstacles(x, v, 0.15, seg, nrm, start, bbox)
    assert bounces == 2
    np.testing.assert_allclose(x, [[0.35, 0.5], [0.465, 0.65], [0.45, 0.9]], atol=1e-14)
    np.testing.assert_allclose(v, [[-1.0, 0.0, 0.2], [0.1, 1.0, 0.0], [1.0, 0.0, 0.0]])
    # a particle trapped between two bodies bounces back and forth within one step
    left, right = square(0.2, 0.5, 0.2), square(0.8, 0.5, 0.2)  # the gap 0.3 < x < 0.7
    seg, nrm, start, bbox = obstacle_polygons([left, right], 0.01)
    x, v = np.array([[0.5, 0.5]]), np.array([[1.0, 0.0, 0.0]])
    assert fly_past_obstacles(x, v, 0.9, seg, nrm, start, bbox) == 2  # 0.5 → 0.7 → 0.3 → 0.6
    np.testing.assert_allclose(x, [[0.6, 0.5]], atol=1e-13)
    np.testing.assert_allclose(v[0], [1.0, 0.0, 0.0])
    # many random particles at a circle: none ends inside its polygon, speeds unchanged
    rng = np.random.default_rng(5)
    disc = circle(0.5, 0.5, 0.3)
    seg, nrm, start, bbox = obstacle_polygons([disc], 0.02)
    x = rng.uniform(0.0, 1.0, (20000, 2))
    x = x[disc.signed_distance(x[:, 0], x[:, 1]) > 0.01]
    v = rng.normal(0.0, 1.0, (x.shape[0], 3))
    speed = np.linalg.norm(v, axis=1)
    fly_past_obstacles(x, v, 0.05, seg, nrm, start, bbox)
    assert push_out_of_obstacles(x, v, seg, nrm, start, bbox) == 0
    heights = np.einsum("nsd,sd->ns", x[:, None, :] - seg[None, :, 0, :], nrm)
    assert np.all(heights.max(axis=1) >= -1e-12)  # above some face: outside the convex polygon
    np.testing.assert_allclose(np.linalg.norm(v, axis=1), speed, rtol=1e-13)


def test_safeguard_mirrors_points_out_of_whichever_body_holds_them():
    """Points strictly inside any of several bodies are found (against the
    bodies' exact signed distance) and mirrored across the nearest face:
    back outside, at the same distance from it; points outside stay put."""
    from partmesh.cases.shape_factories import circle, square
    from partmesh.particle.dsmc.walls import inside_obstacles, obstacle_polygons, push_out_of_obstacles

    bodies = [square(0.2, 0.5, 0.2), circle(0.5, 0.5, 0.15), square(0.8, 0.3, 0.1)]
    seg, nrm, start, bbox = obstacle_polygons(bodies, 1e-3)
    rng = np.random.default_rng(3)
    x = rng.uniform(0.0, 1.0, (40000, 2))
    depth = np.min([b.signed_distance(x[:, 0], x[:, 1]) for b in bodies], axis=0)
    x = x[np.abs(depth) > 1e-3]  # clear of the circle's chords
    depth = depth[np.abs(depth) > 1e-3]
    inside = depth < 0.0
    assert inside.sum() > 1000 and (~inside).sum() > 1000
    np.testing.assert_array_equal(inside_obstacles(x, seg, nrm, start, bbox), inside)
    # in the squares the nearest face is exact: mirrored to the same distance outside
    moved = x.copy()
    v = np.tile([-1.0, 0.0, 0.0], (x.shape[0], 1))
    assert push_out_of_obstacles(moved, v, seg, nrm, start, bbox) == inside.sum()
    assert not inside_obstacles(moved, seg, nrm, start, bbox).any()
    np.testing.assert_array_equal(moved[~inside], x[~inside])
    in_square = inside & (np.abs(x[:, 0] - 0.5) > 0.2)
    after = np.min([b.signed_distance(moved[:, 0], moved[:, 1]) for b in bodies[::2]], axis=0)
    np.testing.assert_allclose(after[in_square], -depth[in_square], atol=1e-12)


def test_closed_box_with_an_obstacle_keeps_mass_and_energy_and_no_particle_inside():
    import dataclasses

    from partmesh.cases.shape_factories import circle

    # the Sedov blast hits a disc: specular polygon walls conserve energy exactly
    scene = dataclasses.replace(partmesh.scene("sedov", n_out=32, t_end=0.15), obstacles=(circle(0.0, 0.45, 0.2),))
    ds = partmesh.run(scene, "dsmc", dx=2.0 / 32, ppc=20, progress=False)
    assert ds.attrs["mass_drift"] == 0.0
    assert ds.attrs["energy_drift"] < 1e-12
    assert ds.attrs["particles_in_solids"] == 0
    solid = ds["solid"].values.astype(bool)
    assert solid.any() and np.all(np.isnan(ds["rho"].values[:, solid]))
    assert ds.attrs["obstacle_bounces"] > 10  # the disc's walls were at work (74 bounces measured)


@pytest.mark.parametrize("normal", [1.0, -1.0])
def test_outflow_far_field_state_carries_each_characteristic_from_its_side(normal):
    from partmesh.particle.dsmc.far_field import far_field_state

    g = 1.4
    far = (1.2, 0.0, 5.0, 1e5)
    c = lambda s: np.sqrt(g * s[3] / s[0])  # noqa: E731
    # the undisturbed gas at rest: the far state itself
    np.testing.assert_allclose(far_field_state(far, far, 0, normal, g), far, rtol=1e-12)
    # a subsonic outflow: J+ = u_n + 2c/(g-1) from inside, J- = u_n - 2c/(g-1) from far, entropy from far,
    # tangential velocity from inside
    inside = (1.5, normal * 60.0, -3.0, 1.4e5)
    out = far_field_state(inside, far, 0, normal, g)
    un = lambda s: normal * s[1]  # noqa: E731
    assert un(out) + 2 * c(out) / (g - 1) == pytest.approx(un(inside) + 2 * c(inside) / (g - 1), rel=1e-12)
    assert un(out) - 2 * c(out) / (g - 1) == pytest.approx(un(far) - 2 * c(far) / (g - 1), rel=1e-12)
    assert out[3] / out[0] ** g == pytest.approx(far[3] / far[0] ** g, rel=1e-12)
    assert out[2] == inside[2]
    # subsonic inflow through the side: entropy and tangential velocity from far
    inside = (1.5, -normal * 200.0, -3.0, 1.4e5)
    out = far_field_state(inside, far, 0, normal, g)
    assert un(out) < 0.0
    assert out[3] / out[0] ** g == pytest.approx(far[3] / far[0] ** g, rel=1e-12) and out[2] == far[2]
    # supersonic outflow: all from inside
    fast = (1.5, normal * 800.0, 0.0, 1.4e5)
    assert far_field_state(fast, far, 0, normal, g) == fast


@pytest.mark.full
def test_open_sides_hold_an_undisturbed_gas_undisturbed():
    # a uniform gas at rest between two outflow sides: neither the boundary state nor the mass may drift
    scene = partmesh.scene("sod", right_rho=1.0, right_p=1.0, nx_out=50)
    ds = partmesh.run(scene, "dsmc", dx=1 / 50, ppc=200, window=10, progress=False)
    rho, p, u = (ds[q].isel(time=-1).values for q in ("rho", "p", "u"))
    # 200 particles per cell, 10 correlated samples: ~ 5 % scatter per cell (a reservoir copying the last
    # sample drifted to 0.4 and 1.5 next to the sides)
    assert np.abs(rho[:3] - 1.0).max() < 0.15 and np.abs(rho[-3:] - 1.0).max() < 0.15
    assert np.abs(u).max() < 0.2 and abs(p.mean() - 1.0) < 0.03
    # the mean over 8 seeds at 400 cells x 30 particles: +0.3 +- 0.15 %; a reservoir taking its entropy from
    # the noisy layer inside lost 1.6 +- 0.4 %
    scene = partmesh.scene("sod", right_rho=1.0, right_p=1.0, nx_out=400)
    runs = [partmesh.run(scene, "dsmc", dx=1 / 400, ppc=30, seed=s, progress=False) for s in range(8)]
    mass = [ds["rho"].isel(time=-1).mean() for ds in runs]
    assert abs(np.mean(mass) - 1.0) < 0.008


@pytest.mark.full
def test_closed_box_with_obstacles_keeps_every_particle_outside_them_for_10000_steps():
    import dataclasses

    from partmesh.cases.shape_factories import circle, diamond, square, triangle_right
    from partmesh.particle.dsmc.solve import _Gas

    # a Sedov blast in a closed box among four bodies with corners and curved faces
    bodies = (circle(0.0, 0.45, 0.2), square(-0.5, -0.5, 0.3), triangle_right(0.5, -0.4, 0.3), diamond(-0.5, 0.5, 0.25))
    scene = dataclasses.replace(partmesh.scene("sedov", n_out=32), obstacles=bodies)
    gas = _Gas(scene, 2.0 / 32, 10, 2.0, seed=3)
    count, t = gas.x.shape[0], 0.0
    mass0, energy0 = gas.totals()
    inside = []
    for n in range(10_000):
        dt = gas.dx / gas.signal_speed()
        gas.step(t, dt, n)
        t += dt
        if n % 10 == 0:
            inside.append(gas.in_solids())
        assert gas.x.shape[0] == count
    assert gas.bounces > 10 * count  # the bodies were hit, over and over
    assert max(inside) == 0 and gas.in_solids() == 0
    assert gas.safeguard == 0  # the exact segment intersection never needed the push-out safeguard
    mass, energy = gas.totals()
    assert mass == mass0 and energy == pytest.approx(energy0, rel=1e-11)


def test_frames_on_the_run_grid_take_the_steps_cell_sums():
    from partmesh.particle.dsmc.solve import _Gas

    # after steps, the sums the redraw recorded are the moments of the particles as they stand
    scene = partmesh.scene("shock_reflection", Ms=2.0, dim=2)
    gas = _Gas(scene, scene.dx, 10, 2.0, seed=1)
    for n in range(3):
        gas.step(n * 1e-6, 1e-6, n)
    from_sums, from_particles = gas.output_sums(), gas.output_sums()
    assert from_sums.same_grid(gas.cells)
    gas.sample_into(from_sums)
    from_particles.add(gas.x, gas.v, gas.e)
    np.testing.assert_array_equal(from_sums.s0, from_particles.s0)
    np.testing.assert_allclose(from_sums.s1, from_particles.s1, rtol=1e-12, atol=1e-12 * np.abs(gas.v).max())
    np.testing.assert_allclose(from_sums.s2, from_particles.s2, rtol=1e-12)


@pytest.mark.parametrize("interval", [1.0, 2.0, 2.001, 3.999, 5.0005, 7.3])
def test_landing_steps_reach_the_output_time_without_a_sliver(interval):
    """Stepping toward an output time ``interval`` stable steps away lands on
    it exactly, never exceeds the stable step and never takes less than
    half of one (a sliver step would spike the particles' wall force)."""
    dt_max, t, steps = 1e-6, 0.0, []
    t_out = interval * dt_max
    while t < t_out * (1 - 1e-14):
        steps.append(landing_step(dt_max, t_out - t))
        t += steps[-1]
    assert t == pytest.approx(t_out, rel=1e-14)
    assert max(steps) <= dt_max
    assert min(steps) >= 0.5 * dt_max * (1 - 1e-12)
    assert len(steps) == math.ceil(interval - 1e-9)
