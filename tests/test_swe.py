"""The shallow-water model (method ``swe``) against exact solutions, rest
states, conservation and symmetry."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import partmesh
from partmesh.cases.errors import InputError, Unsupported
from partmesh.compare.convergence import observed_order
from partmesh.compare.metrics import field_error
from partmesh.gridref.swe.step import Scheme, hancock_step, radii, stable_dt

G = 9.81


def advance(U, z, scheme, t_end, radius=None):
    """``U`` after ``t_end`` seconds, and the smallest depth met on the way."""
    step = jax.jit(lambda U, dt: hancock_step(U, z, dt, scheme, radius))
    t, smallest = 0.0, float(U[0].min())
    while t < t_end:
        dt = min(float(stable_dt(U, scheme)), t_end - t)
        U = step(U, dt)
        t += dt
        smallest = min(smallest, float(U[0].min()))
    return U, smallest


@pytest.fixture(scope="module")
def dam_break_ladder():
    scene = partmesh.scene("dam_break")
    runs = {n: partmesh.run(scene, "swe", dx=10.0 / n, progress=False) for n in (200, 400, 800)}
    exact = scene.exact(runs[800].time.values)
    return scene, runs, exact


def test_wet_dam_break_matches_stoker(dam_break_ladder):
    # h_left = 1 m, h_right = 0.1 m: rarefaction, middle state h_m = 0.3965 m, bore
    _, runs, exact = dam_break_ladder
    mean_depth = float(exact.h.isel(time=-1).mean())
    errors = {n: field_error(ds.h.isel(time=-1), exact.h.isel(time=-1)) for n, ds in runs.items()}
    assert errors[800] / mean_depth <= 0.01  # acceptance: 1 % (measured 0.07 %)
    # a captured bore: first order in L1 at best, and errors fall with resolution
    order = observed_order([10 / n for n in errors], list(errors.values()))
    assert 0.7 < order < 1.6
    # total volume: the waves have not reached the open ends
    ds = runs[800]
    assert float(ds.h.isel(time=-1).sum()) == pytest.approx(float(exact.h.isel(time=-1).sum()), rel=1e-3)


def test_a_float32_run_follows_the_float64_run(dam_break_ladder):
    # the bench's fast precision: its depths differ from double precision by round-off carried through
    # 400 steps, far below the scheme's own error
    scene, runs, exact = dam_break_ladder
    single = partmesh.run(scene, "swe", dx=10.0 / 800, precision="float32", progress=False)
    h32, h64 = single.h.isel(time=-1), runs[800].h.isel(time=-1)
    assert float(np.abs(h32 - h64).max()) < 1e-4
    assert field_error(h32, exact.h.isel(time=-1)) == pytest.approx(field_error(h64, exact.h.isel(time=-1)), rel=0.02)


def test_ritter_dam_break_keeps_depth_non_negative_and_runs_at_the_front_speed():
    scene = partmesh.scene("dam_break", h_right=0.0, t_end=0.5)
    ds = partmesh.run(scene, "swe", dx=10.0 / 800, progress=False)
    h = ds.h.isel(time=-1)
    assert float(ds.h.min()) >= 0.0
    exact = scene.exact(ds.time.values).h.isel(time=-1)
    assert field_error(h, exact) / float(exact.mean()) < 0.01
    # where the front's depth falls to 1 mm, against Ritter's parabola (2 sqrt(g h_l) - xi)^2/(9 g) = 1 mm
    front = float(ds.x.where(h > 1e-3, drop=True).max())
    assert front == pytest.approx(5.0 + (2 * np.sqrt(G) - np.sqrt(9 * G * 1e-3)) * 0.5, abs=0.15)


@pytest.mark.parametrize("dim", [1, pytest.param(2, marks=pytest.mark.full)])
def test_lake_at_rest_over_a_bumpy_bed_with_a_dry_island_stays_at_rest(dim):
    ds = partmesh.run(partmesh.scene("lake_at_rest", dim=dim), "swe", progress=False)
    assert float(np.nanmax(np.abs(ds.eta))) <= 1e-12
    assert float(np.abs(ds.u).max()) <= 1e-12
    assert float(ds.h.min()) == 0.0  # the island is dry and stays dry
    assert int(ds.eta.isnull().sum()) > 0


def test_radial_lake_at_rest_is_balanced():
    # pressure fluxes through faces of different radii against the hoop term and the bed source
    n, dx = 200, 0.01
    r = (np.arange(n) + 0.5) * dx
    z = -0.5 + 0.6 * np.exp(-(((r - 1.0) / 0.2) ** 2))
    h = np.maximum(-z, 0.0)
    scheme = Scheme(g=G, dx=(dx,), kinds=("axis", "reflect"), radial=True)
    U, smallest = advance((jnp.asarray(h), jnp.zeros(n)), jnp.asarray(z), scheme, 0.5, radii(r, dx))
    assert float(jnp.abs(U[1]).max()) <= 1e-12 and float(jnp.abs(U[0] - h).max()) <= 1e-12
    assert smallest == 0.0


@pytest.mark.full
def test_radial_run_equals_the_2d_run_of_an_axisymmetric_hump():
    # a Gaussian hump 0.1 m high on 1 m of water: the 1D-radial solution against the 2D one along the axis
    n, dx = 100, 0.02
    c = (np.arange(2 * n) - n + 0.5) * dx
    Y, X = np.meshgrid(c, c, indexing="ij")
    h2 = 1.0 + 0.1 * np.exp(-((np.hypot(X, Y) / 0.3) ** 2))
    scheme2 = Scheme(g=G, dx=(dx, dx), kinds=("outflow",) * 4)
    U2, _ = advance((jnp.asarray(h2), jnp.zeros_like(h2), jnp.zeros_like(h2)), jnp.zeros_like(h2), scheme2, 0.3)
    r = (np.arange(n) + 0.5) * dx
    scheme_r = Scheme(g=G, dx=(dx,), kinds=("axis", "outflow"), radial=True)
    Ur, _ = advance((jnp.asarray(1.0 + 0.1 * np.exp(-((r / 0.3) ** 2))), jnp.zeros(n)), jnp.zeros(n), scheme_r, 0.3,
                    radii(r, dx))
    along_x = 0.5 * (np.asarray(U2[0])[n - 1, n:] + np.asarray(U2[0])[n, n:])
    hump = float(np.max(np.asarray(Ur[0]))) - 1.0
    assert hump > 0.01
    assert np.max(np.abs(along_x - np.asarray(Ur[0]))) < 0.01 * 0.1
    # and the 2D solution is symmetric under x <-> y to round-off
    assert float(jnp.max(jnp.abs(U2[0] - U2[0].T))) < 1e-13
    assert float(jnp.max(jnp.abs(U2[1] - U2[2].T))) < 1e-13


def test_closed_basin_conserves_volume_to_round_off():
    n, dx = 64, 1.0 / 64
    c = (np.arange(n) + 0.5) * dx
    Y, X = np.meshgrid(c, c, indexing="ij")
    z = -0.3 + 0.2 * np.exp(-((X - 0.3) ** 2 + (Y - 0.6) ** 2) / 0.01)
    h = np.maximum(0.05 * np.exp(-((X - 0.6) ** 2 + (Y - 0.5) ** 2) / 0.005) - z, 0.0)
    scheme = Scheme(g=G, dx=(dx, dx), kinds=("reflect",) * 4)
    U, smallest = advance((jnp.asarray(h), jnp.zeros_like(h), jnp.zeros_like(h)), jnp.asarray(z), scheme, 0.5)
    assert float(jnp.sum(U[0])) == pytest.approx(float(np.sum(h)), rel=1e-13)
    assert smallest >= 0.0


@pytest.mark.full
def test_absorbing_side_lets_a_long_wave_leave():
    # a hump of 1 cm on 1 m of water splits into two long waves; each end of the channel either
    # reflects them (wall) or lets them leave (absorbing)
    n, dx = 400, 0.05
    x = (np.arange(n) + 0.5) * dx
    h = 1.0 + 0.01 * np.exp(-(((x - 10.0) / 0.5) ** 2))
    left = {}
    for kind in ("reflect", "absorbing"):
        scheme = Scheme(g=G, dx=(dx,), kinds=(kind, kind))
        # (the bed at z = -1 m: the still surface is at 0, the level the absorbing side lets waves leave to)
        U, _ = advance((jnp.asarray(h), jnp.zeros(n)), jnp.full(n, -1.0), scheme, 6.0)  # c t = 18.8 m: gone and back
        left[kind] = float(jnp.max(jnp.abs(U[0] - 1.0)))
    assert left["reflect"] > 0.004
    assert left["absorbing"] < 0.02 * 0.005  # < 2 % of each wave's 5 mm


def test_water_and_gas_methods_refuse_each_others_scenes():
    with pytest.raises(Unsupported, match=r"^method fv runs gas scenes, and dam_break is a water scene\.$"):
        partmesh.run(partmesh.scene("dam_break"), "fv")
    with pytest.raises(Unsupported, match=r"^method swe runs water scenes, and sod is a gas scene\.$"):
        partmesh.run(partmesh.scene("sod"), "swe")


@pytest.mark.parametrize("settings, word", [({"cfl": 0.8}, "cfl"), ({"limiter": "magic"}, "limiter"),
                                            ({"dx": -1.0}, "dx"), ({"order": 3}, "order"),
                                            ({"precision": "float16"}, "precision")])
def test_bad_settings_name_the_parameter(settings, word):
    with pytest.raises(InputError, match=word):
        partmesh.run(partmesh.scene("dam_break"), "swe", progress=False, **settings)


def test_dam_break_scene_refuses_a_run_longer_than_its_channel():
    with pytest.raises(InputError, match=r"t_end = 5 s lets the waves of the dam break leave"):
        partmesh.scene("dam_break", t_end=5.0)


def test_small_prins_mound_gauge_record_matches_the_long_wave_limit():
    # Q = 1.2 cm on 0.7 m (Q/d = 0.017): the shallow-water model is the non-dispersive linear limit,
    # d'Alembert's half-height box passing the gauge at 4.57 m; away from its two fronts (smeared over a
    # few cells, and shifted by the small nonlinearity) the records agree within 2 % of Q
    from partmesh.compare import exact

    scene = partmesh.scene("prins_mound", Q=0.012, t_end=3.0)
    ds = partmesh.run(scene, "swe", dx=0.02, progress=False)
    t = ds.t_probe.values
    limit, _ = exact.linear_wave_fields(exact.Mound(0.012, 0.61), [4.57], t, 0.7, dispersive=False)
    record = ds.eta_probe.sel(probe="x4.57").values
    c = np.sqrt(G * 0.7)
    away = (np.abs(t - (4.57 - 0.61) / c) > 0.1) & (np.abs(t - (4.57 + 0.61) / c) > 0.1)
    assert np.max(np.abs(record - limit[:, 0])[away]) <= 0.02 * 0.012
    assert record.max() == pytest.approx(0.006, rel=0.02)  # the plateau, Q/2


def test_wave_scenes_refuse_a_flume_short_enough_for_reflections_to_reach_the_gauges():
    with pytest.raises(InputError, match=r"^length = 12 m lets a wave reflected at the far end reach the gauges"):
        partmesh.scene("prins_mound", length=12.0)


@pytest.mark.full
def test_a_dam_across_a_square_basin_breaks_as_in_one_dimension():
    # dim=2: the dam spans the basin between walls at y = 0 and 10 m, so the flow stays 1D (the bench problem)
    flat, square = partmesh.scene("dam_break", nx_out=100), partmesh.scene("dam_break", nx_out=100, dim=2)
    a, b = (partmesh.run(scene, "swe", progress=False) for scene in (flat, square))
    h = b.h.isel(time=-1).values
    assert np.abs(h - h[:1]).max() < 1e-12  # every row alike, and no velocity across
    assert float(np.abs(b.v).max()) < 1e-12
    error_2d = field_error(b.h.isel(time=-1), square.exact(b.time.values).h.isel(time=-1))
    error_1d = field_error(a.h.isel(time=-1), flat.exact(a.time.values).h.isel(time=-1))
    assert error_2d == pytest.approx(error_1d, rel=0.05)
