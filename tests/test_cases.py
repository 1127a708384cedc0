"""The scene registry and the scenes' data (SPEC §4): names, parameters,
probes, boundary states — checked against the numbers SPEC §4 prints."""

from __future__ import annotations

import math

import numpy as np
import pytest

import partmesh
from partmesh.cases.scene import Inflow, Scene, WaterScene

REQUIRED_SCENES = ("sod", "shock_reflection", "wedge", "sedov", "noh", "blast_wall", "cylinder_shock")

REQUIRED_PARAMETERS = {
    "sod": ("left_rho", "left_u", "left_p", "right_rho", "right_u", "right_p", "x0", "t_end"),
    "shock_reflection": ("Ms", "rho0", "p0", "length", "t_end"),
    "wedge": ("M1", "theta_deg"),
    "sedov": ("E", "rho0", "p0", "t_end"),
    "blast_wall": ("blast", "negative_phase", "dim"),
}


def test_registry_lists_the_spec_scenes():
    names = partmesh.scenes()
    assert names == sorted(names)
    for name in REQUIRED_SCENES:
        assert name in names


@pytest.mark.parametrize("name", REQUIRED_SCENES)
def test_required_parameters_exist(name):
    params = partmesh.scene_parameters(name)
    for key in REQUIRED_PARAMETERS.get(name, ()):
        assert key in params, f"{name} lacks parameter {key}"


@pytest.fixture(scope="module", params=sorted(set(partmesh.scenes()) | set(REQUIRED_SCENES)))
def default_scene(request):
    return partmesh.scene(request.param)


def test_every_scene_builds_with_defaults(default_scene):
    scene = default_scene
    assert isinstance(scene, (Scene, WaterScene))
    assert scene.name in partmesh.scenes()
    assert scene.dim in (1, 2, 3) and len(scene.domain) == scene.dim
    for side in scene.sides:
        bc = scene.boundaries[side]
        assert (isinstance(bc, Inflow) and scene.medium == "gas") or bc in scene.boundary_kinds
    times = np.asarray(scene.output.times)
    assert times.size >= 1 and np.all(np.diff(times) > 0)
    assert times[0] >= 0 and times[-1] <= scene.t_end * (1 + 1e-12)
    assert scene.output.domain == scene.domain
    # the scene's parameters are what it stores in every result
    assert scene.to_dict()["case"] == scene.name


def test_probes_lie_inside_the_domain_and_outside_solids(default_scene):
    scene = default_scene
    for probe in scene.probes:
        for c, (lo, hi) in zip(probe.at(scene.dim), scene.domain):
            assert lo <= c <= hi, (scene.name, probe)
        for shape in scene.obstacles:
            assert shape.signed_distance(np.array(probe.x), np.array(probe.y)) >= 0, (scene.name, probe)


def test_default_resolution_divides_the_domain(default_scene):
    scene = default_scene
    for lo, hi in scene.domain:
        n = (hi - lo) / scene.dx
        assert n == pytest.approx(round(n), abs=1e-6)


def test_initial_state_is_physical(default_scene):
    scene = default_scene
    grid = [scene.output.centres(a) for a in range(scene.dim)]
    if scene.dim == 1:
        X, Y, Z = grid[0], None, ()
    else:
        X, Y, *Z = np.meshgrid(*grid)
    if scene.medium == "water":
        eta, *velocity = (np.broadcast_to(np.asarray(a, float), X.shape) for a in scene.initial(X, Y))
        depth = eta - np.asarray(scene.bed(X, Y), float)
        assert np.all(np.isfinite(depth)) and np.any(depth > 0)  # water somewhere; land where depth <= 0
    else:
        # (rho, u, v, p), in 3D (rho, u, v, w, p)
        rho, *velocity, p = (np.broadcast_to(np.asarray(a, float), X.shape)
                             for a in scene.initial(X, Y, scene.dx, *Z))
        assert np.all(rho > 0) and np.all(p > 0)
    assert all(np.all(np.isfinite(c)) for c in velocity)


# --- the numbers of SPEC §4.1 ------------------------------------------------


def test_sod_defaults_are_sods():
    s = partmesh.scene("sod")
    p = s.parameters
    assert (p["left_rho"], p["left_u"], p["left_p"]) == (1.0, 0.0, 1.0)
    assert (p["right_rho"], p["right_u"], p["right_p"]) == (0.125, 0.0, 0.1)
    assert p["x0"] == 0.5 and s.t_end == pytest.approx(0.2)
    assert s.domain == ((0.0, 1.0),)
    rho, _, _, pr = s.initial(np.array([0.25, 0.75]), None, 0.01)
    np.testing.assert_allclose(rho, [1.0, 0.125])
    np.testing.assert_allclose(pr, [1.0, 0.1])


def test_sod_presets_are_toros():
    strong = partmesh.scene("sod", preset="strong_shock").parameters
    assert strong["left_p"] / strong["right_p"] == pytest.approx(1e5)
    t123 = partmesh.scene("sod", preset="toro123").parameters
    assert (t123["left_u"], t123["right_u"]) == (-2.0, 2.0)
    assert t123["left_p"] == t123["right_p"] == 0.4


def test_shock_reflection_inflow_is_the_published_post_shock_state():
    """SPEC §4.1: at Ms = 3.2 into rho0 = 1.225, p0 = 101325 the post-shock
    state is rho = 4.03 rho0, p = 11.78 p0, u = 818.83 m/s."""
    s = partmesh.scene("shock_reflection", Ms=3.2)
    assert (s.parameters["rho0"], s.parameters["p0"]) == (1.225, 101325.0)
    inflow = s.boundaries["x_lo"]
    assert isinstance(inflow, Inflow)
    rho, u, v, p = inflow.state(0.0)
    assert rho / 1.225 == pytest.approx(4.03, abs=0.005)
    assert p / 101325.0 == pytest.approx(11.78, abs=0.005)
    assert u == pytest.approx(818.83, abs=0.1)
    assert v == 0.0
    assert s.boundaries["x_hi"] == "reflect"
    probes = {pr.name: pr for pr in s.probes}
    assert "wall" in probes and probes["wall"].x == pytest.approx(s.parameters["length"])


def test_shock_reflection_2d_domain():
    s = partmesh.scene("shock_reflection", dim=2)
    assert s.domain == ((0.0, 0.5), (0.0, 0.125))


def test_wedge_defaults():
    s = partmesh.scene("wedge")
    assert s.parameters["M1"] == 3.5 and s.parameters["theta_deg"] in (10.0, 20.0, 30.0)
    rho, u, _, p = s.boundaries["x_lo"].state(0.0)
    assert u / math.sqrt(1.4 * p / rho) == pytest.approx(3.5, rel=1e-12)
    assert len(s.obstacles) == 1


def test_sedov_domain_and_symmetric_energy_deposit():
    s = partmesh.scene("sedov")
    assert s.domain == ((-1.0, 1.0), (-1.0, 1.0))
    assert all(s.boundaries[side] == "reflect" for side in s.sides)
    # the deposited internal energy integrates to E
    n = 128
    dx = 2.0 / n
    c = -1.0 + (np.arange(n) + 0.5) * dx
    X, Y = np.meshgrid(c, c)
    _, _, _, p = s.initial(X, Y, dx)
    p0 = s.parameters["p0"]
    assert np.sum((p - p0) / 0.4) * dx * dx == pytest.approx(s.parameters["E"], rel=1e-12)
    assert np.array_equal(p, p.T) and np.array_equal(p, p[::-1, ::-1])


def test_noh_defaults_and_initial_velocity():
    s = partmesh.scene("noh")
    p = s.parameters
    assert p["gamma"] == pytest.approx(5.0 / 3.0) and p["rho0"] == 1.0 and p["u0"] == 1.0
    X, Y = np.meshgrid([0.1, 0.5, 0.9], [0.2, 0.7])
    _, u, v, _ = s.initial(X, Y, 0.01)
    np.testing.assert_allclose(np.hypot(u, v), 1.0, rtol=1e-14)
    np.testing.assert_allclose(u * Y - v * X, 0.0, atol=1e-14)  # radial
    assert np.all(u * X + v * Y < 0)  # toward the origin


def test_cylinder_shock_defaults():
    s = partmesh.scene("cylinder_shock")
    assert s.parameters["Ms"] == 1.16 and s.parameters["diameter"] == 0.015
    (body,) = s.obstacles
    x0, y0, x1, y1 = body.bounds()  # (xmin, ymin, xmax, ymax)
    assert x1 - x0 == pytest.approx(0.015) and y1 - y0 == pytest.approx(0.015)


# --- blast_wall (SPEC §4.2) ---------------------------------------------------


def rankine_hugoniot(p_over, rho0=1.0, p0=1.0e5, gamma=1.4):
    """SPEC §4.2: rho = rho0 [(γ+1)p_o + 2γp0]/[(γ−1)p_o + 2γp0],
    u = a0 (p_o/(γp0)) sqrt(2γp0/[(γ+1)p_o + 2γp0]), a0 = sqrt(γp0/rho0)."""
    a0 = math.sqrt(gamma * p0 / rho0)
    rho = rho0 * ((gamma + 1) * p_over + 2 * gamma * p0) / ((gamma - 1) * p_over + 2 * gamma * p0)
    u = a0 * p_over / (gamma * p0) * math.sqrt(2 * gamma * p0 / ((gamma + 1) * p_over + 2 * gamma * p0))
    return rho, u, p0 + p_over


BLASTS = {"moderate": (10.924, 0.473e-3, 4.0), "strong": (100.924, 0.5e-3, 2.72)}


def test_blast_wall_geometry_and_wall_probe():
    s = partmesh.scene("blast_wall")
    assert s.dim == 1 and s.domain == ((0.0, 1.0),)
    assert (s.parameters["rho0"], s.parameters["p0"], s.gamma) == (1.0, 1.0e5, 1.4)
    probes = {pr.name: pr for pr in s.probes}
    assert probes["w"].x == pytest.approx(1.0)
    assert s.boundaries["x_hi"] == "reflect"
    assert s.wall is not None and s.wall.side == "x_hi"
    s2 = partmesh.scene("blast_wall", dim=2)
    assert s2.dim == 2 and s2.domain[0] == (0.0, 1.0)
    assert {pr.name: pr for pr in s2.probes}["w"].x == pytest.approx(1.0)


@pytest.mark.parametrize("blast", ["moderate", "strong"])
def test_blast_wall_inflow_is_rankine_hugoniot_of_friedlander(blast):
    ratio, t_plus, alpha = BLASTS[blast]
    s = partmesh.scene("blast_wall", blast=blast)
    inflow = s.boundaries["x_lo"]
    p0 = 1.0e5
    for t in (0.0, 0.1 * t_plus, 0.5 * t_plus, 0.9 * t_plus):
        p_over = ratio * p0 * (1 - t / t_plus) * math.exp(-alpha * t / t_plus)
        rho, u, v, p = inflow.state(t)
        exp_rho, exp_u, exp_p = rankine_hugoniot(p_over)
        assert (rho, u, p) == pytest.approx((exp_rho, exp_u, exp_p), rel=1e-12), t
        assert v == 0.0
    # the peak state itself, t = 0
    rho, u, v, p = inflow.state(0.0)
    assert p == pytest.approx((1 + ratio) * p0, rel=1e-12)


@pytest.mark.parametrize("blast", ["moderate", "strong"])
def test_blast_wall_negative_phase_none_returns_to_ambient(blast):
    _, t_plus, _ = BLASTS[blast]
    s = partmesh.scene("blast_wall", blast=blast, negative_phase="none")
    for t in (1.01 * t_plus, 2 * t_plus, 5 * t_plus):
        assert s.boundaries["x_lo"].state(t) == pytest.approx((1.0, 0.0, 0.0, 1.0e5), abs=1e-9)


def test_blast_wall_friedlander_negative_phase_is_an_underpressure():
    _, t_plus, _ = BLASTS["moderate"]
    s = partmesh.scene("blast_wall", negative_phase="friedlander")
    rho, u, _, p = s.boundaries["x_lo"].state(1.5 * t_plus)
    assert p < 1.0e5 and rho < 1.0 and u < 0.0


def test_string_overrides_are_converted():
    s = partmesh.scene("sod", left_rho="2.0", nx_out="200", x0="0.25")
    assert s.parameters["left_rho"] == 2.0 and isinstance(s.parameters["left_rho"], float)
    assert s.parameters["nx_out"] == 200 and s.output.shape == (200,)
    assert s.parameters["x0"] == 0.25
    r = partmesh.scene("shock_reflection", Ms="1.5", dim="2")
    assert r.parameters["Ms"] == 1.5 and r.dim == 2
    b = partmesh.scene("blast_wall", blast="strong", t_end="1e-3")
    assert b.t_end == pytest.approx(1e-3)
    assert partmesh.scene("sod", left_rho="none").parameters["left_rho"] == 1.0  # "none" = the preset's value
    # a yes/no parameter reads the words that checkpoint's resume reads, and refuses any other
    assert partmesh.scene("blast_array", one_period="false").parameters["one_period"] is False
    assert partmesh.scene("blast_array", one_period="Yes").parameters["one_period"] is True
    with pytest.raises(partmesh.InputError, match="blast_array: parameter one_period must be true or false, got 'ture'"):
        partmesh.scene("blast_array", one_period="ture")
