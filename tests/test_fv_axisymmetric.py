"""fv in geometries of revolution (r–z, cylinder, sphere): a gas at rest
stays at rest, a closed body keeps its mass and energy, a state uniform
along the axis steps exactly as the 1D cylinder, the point blast as a
sphere against Sedov–Taylor, and the refusals of a bad axisymmetric
scene."""

import dataclasses
import math

import jax.numpy as jnp
import numpy as np
import pytest

import partmesh
from partmesh.cases.charges import sedov_spherical
from partmesh.cases.errors import InputError, Unsupported
from partmesh.cases.scene import Probe
from partmesh.cases.shapes import Circle, Polygon
from partmesh.gridref.euler.immersed import immersed_boundary
from partmesh.gridref.euler.state import conservative, primitive
from partmesh.gridref.euler.step import Scheme, Stepper
from partmesh.gridref.grid import solver_grid
from partmesh.gridref.jax_setup import configure_jax
from partmesh.gridref.revolution import REVOLUTION, cell_volumes, hoop, revolved

configure_jax()
H = 1e-3
GAMMA = 1.4


def _stepped(W, k, steps, dt=None):
    """``(U, dt)`` after ``steps`` steps of the closed box (every side reflecting) from the primitive ``W``,
    of the stable step or of a fixed ``dt``."""
    U = conservative(tuple(jnp.asarray(a, float) for a in W), GAMMA)
    dim = U[0].ndim
    stepper = Stepper(Scheme(gamma=GAMMA, dx=(H,) * dim, kinds=("reflect",) * (2 * dim), radial=k))
    step = float(stepper.initial_dt(U)) if dt is None else dt
    for _ in range(steps):
        U, stable, _, _ = stepper(U, step, 0.0)
        step = stable if dt is None else dt
    return U


def _totals(U, k):
    weight = revolved(U[0].shape, H, k)
    return np.array([float(np.sum(weight * np.asarray(U[i]))) for i in (0, -1)])


def _hot_spot(shape):
    """A hot, dense blob off the axis (2D) or a hot shell (1D)."""
    centres = [(np.arange(n) + 0.5) * H for n in shape[::-1]]
    if len(shape) == 1:
        hot = np.abs(centres[0] - 0.01) < 0.006
    else:
        Y, X = np.meshgrid(centres[1], centres[0], indexing="ij")
        hot = np.hypot(X - 0.01, Y - 0.016) < 0.006
    zero = np.zeros(shape)
    return (np.where(hot, 3.0, 1.0), *([zero] * len(shape)), np.where(hot, 1e6, 1e5))


def test_face_areas_and_volumes_of_revolution_add_up_to_the_body():
    n = 50
    for k, body in ((1, math.pi * (n * H) ** 2), (2, 4.0 / 3.0 * math.pi * (n * H) ** 3)):
        assert REVOLUTION[k] * np.sum(cell_volumes(0, n, H, k)) * H == pytest.approx(body, rel=1e-13)
        r = (np.arange(n) + 0.5) * H
        np.testing.assert_allclose(hoop(0, n, H, k)[5:], k / r[5:], rtol=3e-3)  # g ≈ k / r away from the axis
    np.testing.assert_allclose(hoop(-3, 6, H, 1)[:3], -hoop(0, 3, H, 1)[::-1], rtol=1e-14)  # mirrored beyond the axis


@pytest.mark.parametrize("k, shape", [(1, (32, 40)), (1, (40,)), (2, (40,))], ids=["r-z", "cylinder", "sphere"])
def test_a_gas_at_rest_in_a_body_of_revolution_stays_at_rest_for_1000_steps(k, shape):
    zero = np.zeros(shape)
    U = _stepped((np.ones(shape), *([zero] * len(shape)), np.full(shape, 1e5)), k, 1000)
    W = primitive(U, GAMMA)
    c = math.sqrt(GAMMA * 1e5)
    assert max(float(jnp.max(jnp.abs(v))) for v in W[1:-1]) < 1e-12 * c
    assert float(jnp.max(jnp.abs(W[0] - 1.0))) < 1e-12


@pytest.mark.parametrize("k, shape", [(1, (32, 40)), (2, (40,))], ids=["r-z", "sphere"])
def test_a_closed_body_of_revolution_keeps_its_mass_and_energy_to_round_off(k, shape):
    W = _hot_spot(shape)
    before = _totals(conservative(tuple(jnp.asarray(a) for a in W), GAMMA), k)
    U = _stepped(W, k, 300)
    assert float(jnp.max(jnp.abs(primitive(U, GAMMA)[1]))) > 10.0  # the blob has expanded and reflected
    np.testing.assert_allclose(_totals(U, k), before, rtol=1e-13)


def _bodies_of_revolution():
    """A sphere on the axis (its half cross-section touching x = 0) and a ring (a torus) off it, in a closed
    r–z box, on the cut-cell grid."""
    grid = solver_grid(((0.0, 0.04), (0.0, 0.05)), H)
    theta = np.linspace(-np.pi / 2, np.pi / 2, 41)
    half_disc = Polygon(np.stack([0.008 * np.cos(theta), 0.035 + 0.008 * np.sin(theta)], axis=1))
    return immersed_boundary(grid, [half_disc, Circle(0.025, 0.02, 0.006)], (False, False), radial=1)


@pytest.mark.full
def test_a_gas_at_rest_around_bodies_of_revolution_stays_at_rest():
    """The wall vector closes every ring cut cell against its faces and its hoop source."""
    ib = _bodies_of_revolution()
    shape = ib.shape
    U = conservative((jnp.ones(shape), jnp.zeros(shape), jnp.zeros(shape), jnp.full(shape, 1e5)), GAMMA)
    stepper = Stepper(Scheme(gamma=GAMMA, dx=(H, H), kinds=("reflect",) * 4, radial=1), immersed=ib, solid_state=U)
    dt = float(stepper.initial_dt(U))
    for _ in range(200):
        U, dt, _, _ = stepper(U, dt, 0.0)
    W = [np.asarray(a)[ib.fluid] for a in primitive(U, GAMMA)]
    assert np.max(np.hypot(W[1], W[2])) < 1e-12 * math.sqrt(GAMMA * 1e5)
    assert np.max(np.abs(W[0] - 1.0)) < 1e-12


@pytest.mark.full
def test_a_closed_cylinder_around_bodies_of_revolution_keeps_its_mass_and_energy():
    ib = _bodies_of_revolution()
    W = _hot_spot(ib.shape)
    U = conservative(tuple(jnp.asarray(a) for a in W), GAMMA)
    stepper = Stepper(Scheme(gamma=GAMMA, dx=(H, H), kinds=("reflect",) * 4, radial=1), immersed=ib, solid_state=U)
    weight = ib.volume * revolved(ib.shape, H, 1)
    before = np.array([float(np.sum(weight * np.asarray(U[i]))) for i in (0, -1)])
    dt = float(stepper.initial_dt(U))
    for _ in range(300):
        U, dt, _, _ = stepper(U, dt, 0.0)
    assert float(jnp.max(jnp.abs(primitive(U, GAMMA)[1]))) > 100.0  # the blast has met the bodies
    np.testing.assert_allclose([float(np.sum(weight * np.asarray(U[i]))) for i in (0, -1)], before, rtol=1e-13)


@pytest.mark.full
def test_a_state_uniform_along_the_axis_steps_as_the_cylinder():
    ny, nx = 8, 40
    W1 = _hot_spot((nx,))
    W2 = (*(np.broadcast_to(a, (ny, nx)) for a in W1[:2]), np.zeros((ny, nx)), np.broadcast_to(W1[2], (ny, nx)))
    dt = 5e-7
    U1, U2 = _stepped(W1, 1, 40, dt), _stepped(W2, 1, 40, dt)
    for a, b in zip((U2[0], U2[1], U2[3]), U1):
        np.testing.assert_allclose(np.asarray(a), np.broadcast_to(np.asarray(b), (ny, nx)), rtol=1e-12,
                                   atol=1e-12 * float(jnp.max(jnp.abs(b))))
    assert float(jnp.max(jnp.abs(U2[2]))) == 0.0


def test_the_spherical_point_blast_in_r_z_meets_sedov_taylor_and_stays_spherical():
    """At 100 cells across the quadrant: the radius within 2 % and its spread over polar angle within 1 %
    (0.93 % and 0.41 % at 128 cells)."""
    ds = partmesh.run("sedov_spherical", "fv", dx=1e-2, progress=False)
    assert ds.attrs["geometry"] == "axisymmetric"
    assert abs(ds.attrs["shock_radius"] / ds.attrs["shock_radius_exact"] - 1.0) < 0.02
    assert ds.attrs["shock_radius_spread"] < 0.01
    assert ds.attrs["mass_drift"] < 1e-13 and ds.attrs["energy_drift"] < 1e-13


def test_an_axisymmetric_scene_is_refused_where_it_cannot_be():
    scene = sedov_spherical()
    cases = [
        (dict(obstacles=(Circle(0.0, 0.5, 0.1),)), "crosses the axis (it reaches r = -0.1 m)"),
        (dict(probes=(Probe("g", -0.2, 0.1),)), "lies at r = -0.2 m"),
        (dict(domain=((0.1, 1.0), (0.0, 1.0))), "must start at 0, got 0.1 m"),
        (dict(boundaries={**scene.boundaries, "x_lo": "outflow"}), "must be 'reflect'"),
        (dict(geometry="spherical"), "a spherical scene is 1D"),
        (dict(geometry="conical"), "geometry must be one of"),
    ]
    for change, words in cases:
        with pytest.raises(InputError) as error:
            dataclasses.replace(scene, **change)
        assert words in str(error.value)
    with pytest.raises(Unsupported, match="runs planar scenes, and sedov_spherical is axisymmetric"):
        partmesh.run(scene, "hybrid", progress=False)


@pytest.mark.parametrize("W", [0.0, -1.0, 1e7])
def test_a_charge_outside_its_range_is_refused_in_one_sentence(W):
    with pytest.raises(InputError, match=r"^W must lie in \[0.001, 1e\+06\], got"):
        partmesh.scene("surface_burst", W=W)


def test_ring_cells_hold_the_ball_and_the_shells_they_cover_to_round_off():
    from partmesh.cases.ball import ball_density, ring_volumes, shells_remapped

    dx, n = 0.01, 60
    c = (np.arange(n) + 0.5) * dx
    Z, R = np.meshgrid(c, c, indexing="ij")
    volumes = ring_volumes(R, dx)
    assert np.sum(ball_density(R, Z, 0.137, dx) * volumes) == pytest.approx(0.5, rel=1e-14)  # the quadrant's half
    edges = np.arange(41) * 0.003
    contents = np.random.default_rng(2).random(40)
    mean = shells_remapped(R, Z, dx, edges, contents, 2.0)
    shells = 0.5 * np.sum(contents * 4.0 / 3.0 * np.pi * np.diff(edges ** 3))
    rest = 2.0 * (np.sum(volumes) - 0.5 * 4.0 / 3.0 * np.pi * edges[-1] ** 3)
    assert np.sum(mean * volumes) == pytest.approx(shells + rest, rel=1e-14)
    np.testing.assert_allclose(shells_remapped(R, Z, dx, edges, np.full(40, 3.0), 3.0), 3.0, rtol=1e-14)


def test_the_surface_burst_starts_from_its_1d_sphere_with_the_same_mass_and_energy():
    """The remap onto r–z holds half the sphere's mass and energy (its hemisphere) to round-off."""
    from partmesh.cases.charges import remapped, surface_burst, surface_burst_1d

    scene = surface_burst()
    sphere = partmesh.run(surface_burst_1d(t_end=2e-5, n_out=1600), "fv", progress=False)  # (coarser than its own)
    started = remapped(scene, sphere)
    assert started.t_start == pytest.approx(2e-5) and "remapped" in started.parameters["started_from"]
    dx = scene.domain[0][1] / 400
    c = (np.arange(400) + 0.5) * dx
    Z, R = np.meshgrid(c, c, indexing="ij")
    rho, u, v, p = started.initial(R, Z, dx)
    volume = 2.0 * np.pi * R * dx * dx
    energy = p / (GAMMA - 1.0) + 0.5 * rho * (u * u + v * v)
    last = sphere.isel(time=-1)
    r1 = np.asarray(sphere.x)
    edges = np.concatenate([[0.0], 0.5 * (r1[1:] + r1[:-1]), [r1[-1] + 0.5 * (r1[1] - r1[0])]])
    shells = 4.0 / 3.0 * np.pi * np.diff(edges ** 3)
    sphere_energy = np.asarray(last.p) / (GAMMA - 1.0) + 0.5 * np.asarray(last.rho * last.u ** 2)
    beyond = np.sum(volume) - 0.5 * np.sum(shells)  # the air of the quadrant outside the sphere's reach
    rho0, p0 = scene.parameters["rho0"], scene.parameters["p0"]
    assert np.sum(rho * volume) == pytest.approx(0.5 * np.sum(np.asarray(last.rho) * shells) + rho0 * beyond,
                                                 rel=1e-13)
    assert np.sum(energy * volume) == pytest.approx(0.5 * np.sum(sphere_energy * shells)
                                                    + p0 / (GAMMA - 1.0) * beyond, rel=1e-12)


def test_the_wall_load_of_a_disc_is_its_pressure_over_the_whole_disc():
    """A gas at rest at p1 in a closed cylinder loads its top disc with (p1 − p0) π R², in N."""
    from partmesh.cases.parts import Wall

    p0, p1 = 1e5, 3e5
    scene = dataclasses.replace(sedov_spherical(t_end=1e-3, n_out=32), initial=lambda x, y, dx: (1.0, 0.0, 0.0, p1),
                                wall=Wall("y_hi", p0, 1.0), measure=None)
    ds = partmesh.run(scene, "fv", progress=False)
    assert ds.wall_force.attrs["units"] == "N"
    np.testing.assert_allclose(ds.wall_force.values, (p1 - p0) * math.pi * 1.0 ** 2, rtol=1e-12)
    assert float(ds.wall_impulse[-1]) == pytest.approx((p1 - p0) * math.pi * 1e-3, rel=1e-9)


def test_a_surface_burst_is_refused_before_its_1d_sphere_runs():
    with pytest.raises(Unsupported, match="runs planar scenes, and surface_burst is axisymmetric"):
        partmesh.run("surface_burst", "hybrid", progress=False)
    with pytest.raises(InputError, match="has no setting 'limitr'"):
        partmesh.run("surface_burst", "fv", limitr="mc", progress=False)
    with pytest.raises(InputError, match=r"^t_end must be later than 0.00025 s"):
        partmesh.scene("surface_burst", t_end=1e-4)


def test_a_run_that_would_end_before_its_scene_starts_is_refused():
    started = dataclasses.replace(sedov_spherical(n_out=32), t_start=0.1, output=dataclasses.replace(
        sedov_spherical(n_out=32).output, times=(0.2, 0.5)))
    with pytest.raises(InputError, match=r"^t_end must be later than the time scene sedov_spherical starts at"):
        partmesh.run(started, "fv", t_end=0.05, progress=False)


def test_a_1d_wall_of_revolution_is_refused():
    from partmesh.cases.parts import Wall

    sphere = partmesh.scene("surface_burst_1d")
    with pytest.raises(InputError, match="a target wall needs a planar scene in 1D"):
        dataclasses.replace(sphere, wall=Wall("x_hi", 1e5, 1.0))


@pytest.mark.slow
def test_the_1d_sphere_of_a_surface_burst_meets_kingery_bulmash_from_z_2_to_12():
    """A 1 kg Brode balloon as the sphere of 2 kg in free air, 4000 cells (4 mm): peak overpressure, raw and
    fitted behind the shock, within 5 % and arrival within 7 % of Swisdak's fits at Z = 2 … 12 (measured: raw
    +1.4, −1.4, −0.3, −1.3, −4.4 %; fitted +4.1, +1.1, +2.3, +1.2, −1.8 %; −6.1 … −0.6 %), the positive impulse
    within 25 % (−21 … −14 %: an ideal-gas balloon is not a detonation)."""
    ds = partmesh.run("surface_burst_1d", "fv", dx=4e-3, progress=False)
    for z in ("Z2", "Z3", "Z5", "Z8", "Z12"):
        ratio = {q: ds.attrs[f"{z}_{q}"] / ds.attrs[f"{z}_{q.removesuffix('_fitted')}_kb"] - 1.0
                 for q in ("peak_overpressure", "peak_overpressure_fitted", "arrival_time", "positive_impulse")}
        assert abs(ratio["peak_overpressure"]) < 0.05, (z, ratio)
        assert abs(ratio["peak_overpressure_fitted"]) < 0.05, (z, ratio)
        assert abs(ratio["arrival_time"]) < 0.07, (z, ratio)
        assert abs(ratio["positive_impulse"]) < 0.25, (z, ratio)
