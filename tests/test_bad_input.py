"""Bad input is refused with one clear sentence naming the parameter
(SPEC §9): the exception type, the parameter in the message, one line."""

from __future__ import annotations

import dataclasses
import re
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

import partmesh
from partmesh.cases.errors import InputError, SolverFailed
from partmesh.cases.scene import OutputGrid, Probe, Scene
from partmesh.cases.shapes import Circle
from partmesh.compare.io import read
from partmesh.compare.schema import SchemaError


def one_sentence(err) -> str:
    message = str(err)
    assert message and "\n" not in message, repr(message)
    assert "Traceback" not in message
    return message


def tube(**changes):
    """A valid 1D scene built by hand; ``changes`` replace its fields."""
    fields = {
        "name": "tube", "parameters": {}, "dim": 1, "domain": ((0.0, 1.0),), "gamma": 1.4,
        "initial": lambda x, y, dx: (1.0, 0.0, 0.0, 1.0),
        "boundaries": {"x_lo": "reflect", "x_hi": "reflect"},
        "output": OutputGrid(domain=((0.0, 1.0),), shape=(50,), times=(0.05, 0.1), dt_probe=1e-3),
        "dx": 0.02, "t_end": 0.1, "probes": (Probe("mid", 0.5),),
    }
    return Scene(**{**fields, **changes})


@pytest.fixture(scope="module")
def sod():
    return partmesh.scene("sod")


def test_valid_hand_built_scene_is_accepted():
    assert tube().name == "tube"


def test_unknown_case():
    with pytest.raises(InputError) as info:
        partmesh.scene("nope")
    message = one_sentence(info.value)
    assert "nope" in message and "case" in message
    assert "sod" in message  # says what is allowed


def test_unknown_method(sod):
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "nope")
    message = one_sentence(info.value)
    assert "nope" in message and "method" in message and "fv" in message


def test_unknown_scene_parameter():
    with pytest.raises(InputError) as info:
        partmesh.scene("sod", left_density=2.0)
    message = one_sentence(info.value)
    assert "left_density" in message and "left_rho" in message


def test_unknown_solver_setting(sod):
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "fv", limitter="mc", progress=False)
    assert "limitter" in one_sentence(info.value)


@pytest.mark.parametrize("key, value", [("left_rho", -1.0), ("right_rho", 0.0)])
def test_non_positive_density(key, value):
    with pytest.raises(InputError) as info:
        partmesh.scene("sod", **{key: value})
    message = one_sentence(info.value)
    assert key in message and "0" in message


@pytest.mark.parametrize("key", ["left_p", "right_p"])
def test_zero_pressure(key):
    with pytest.raises(InputError) as info:
        partmesh.scene("sod", **{key: 0.0})
    assert key in one_sentence(info.value)


@pytest.mark.parametrize("case, key", [("shock_reflection", "p0"), ("sedov", "rho0"), ("blast_wall", "p0"),
                                       ("noh", "rho0"), ("wedge", "p0")])
def test_non_positive_ambient_state(case, key):
    with pytest.raises(InputError) as info:
        partmesh.scene(case, **{key: -1.0})
    assert key in one_sentence(info.value)


def test_non_numeric_override():
    with pytest.raises(InputError) as info:
        partmesh.scene("sod", left_rho="heavy")
    message = one_sentence(info.value)
    assert "left_rho" in message and "heavy" in message


@pytest.mark.parametrize("cfl", [0.0, -0.5, 1.5])
def test_cfl_outside_0_1(sod, cfl):
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "fv", cfl=cfl, progress=False)
    message = one_sentence(info.value)
    assert "cfl" in message and "(0, 1]" in message


@pytest.mark.parametrize("seed", [-1, 2**63, "12.5"])
def test_a_dsmc_seed_outside_64_bit_integers_is_refused_in_one_sentence(sod, seed):
    # the kernels take the seed as a signed 64-bit integer: 2**63 reached numba as an OverflowError
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "dsmc", seed=seed, ppc=5, progress=False)
    message = one_sentence(info.value)
    assert "seed" in message and (str(2**63 - 1) in message or "integer" in message)


def test_an_ensemble_whose_last_seed_is_past_64_bit_integers_is_refused_before_it_starts(sod):
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "dsmc", seed=2**63 - 2, ensembles=3, ppc=5, progress=False)
    assert "seed" in one_sentence(info.value)


@pytest.mark.parametrize("key, value", [("limiter", "nonsense"), ("riemann", "roe-ish")])
def test_unknown_limiter_or_riemann_solver(sod, key, value):
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "fv", progress=False, **{key: value})
    message = one_sentence(info.value)
    assert key in message and value in message


def test_probe_outside_the_domain():
    with pytest.raises(InputError) as info:
        tube(probes=(Probe("far_away", 1.5),))
    message = one_sentence(info.value)
    assert "far_away" in message and "domain" in message


def test_probe_inside_a_solid():
    from partmesh.cases.shapes import Circle

    scene = partmesh.scene("cylinder_shock")
    body = scene.obstacles[0]
    (x0, y0, x1, y1) = body.bounds()
    with pytest.raises(InputError) as info:
        Scene(**{**scene.__dict__, "probes": (Probe("buried", 0.5 * (x0 + x1), 0.5 * (y0 + y1)),)})
    assert "buried" in one_sentence(info.value)
    assert isinstance(body, Circle)


@pytest.mark.parametrize("times", [(0.1, 0.05), (0.05, 0.05), (0.05, 0.2), (-0.01, 0.05)])
def test_inconsistent_output_times(times):
    with pytest.raises(InputError) as info:
        tube(output=OutputGrid(domain=((0.0, 1.0),), shape=(50,), times=times, dt_probe=1e-3))
    assert "output times" in one_sentence(info.value)


def test_dx_that_does_not_divide_the_domain(sod):
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "fv", dx=0.3, progress=False)
    message = one_sentence(info.value)
    assert "dx" in message and "0.3" in message


def test_non_positive_dx(sod):
    with pytest.raises(InputError) as info:
        partmesh.run(sod, "fv", dx=-1e-3, progress=False)
    assert "dx" in one_sentence(info.value)


@pytest.mark.parametrize("method", ["fv", "sph"])
def test_obstacle_too_coarse_for_dx(method):
    scene = partmesh.scene("cylinder_shock")  # 15 mm cylinder
    with pytest.raises(InputError) as info:
        partmesh.run(scene, method, dx=5e-3, progress=False)  # 3 cells (particle spacings) across it
    assert "dx" in one_sentence(info.value)


@pytest.mark.parametrize("method", ["fv", "sph"])
@pytest.mark.parametrize("case, centre, side", [("cylinder_shock", (0.005, 0.03), "x_lo"),
                                                 ("blast_wall", (0.5, 0.11), "y_hi")])
def test_obstacle_reaching_an_inflow_or_periodic_side(method, case, centre, side):
    # a cylinder across the inlet (the buffer carries no solid) or across a periodic side
    scene = partmesh.scene(case, dim=2) if case == "blast_wall" else partmesh.scene(case)
    scene = dataclasses.replace(scene, obstacles=(Circle(*centre, 0.02),))
    with pytest.raises(InputError) as info:
        partmesh.run(scene, method, dx=2e-3, progress=False)
    message = one_sentence(info.value)
    assert "obstacle 0" in message and side in message


@pytest.mark.full
def test_unstable_sph_run_stops_with_its_partial_result():
    # a pressure ratio of 1e5 without artificial viscosity or conduction cannot be run
    scene = partmesh.scene("sod", left_p=1e5)
    with pytest.raises(SolverFailed) as info:
        partmesh.run(scene, "sph", dx=1 / 200, alpha_max=0.0, alpha_u=0.0, cfl=1.0, progress=False)
    message = one_sentence(info.value)
    # caught in the density solve or in the energy after the step, whichever comes first: when and where
    assert message.startswith(("sph failed at t = ", "sph became unstable at t = ")) and "x = " in message
    partial = info.value.partial
    assert partial.attrs["status"] == "failed" and partial.attrs["failure"] == str(info.value)
    assert 0.0 < float(partial.time[-1]) < scene.t_end
    assert np.all(np.isfinite(partial.rho.isel(time=-1))) and float(partial.rho.isel(time=-1).min()) > 0.0


@pytest.mark.full
def test_sph_support_wider_than_half_a_period_stops_in_one_sentence():
    # one row pitch (0.04 m) at 4 mm: supports of 16 mm that must grow beyond the 20 mm minimum images allow
    scene = partmesh.scene("blast_array", one_period=True)
    with pytest.raises(SolverFailed) as info:
        partmesh.run(scene, "sph", dx=4e-3, t_end=1e-4, progress=False)
    message = one_sentence(info.value)
    assert "reached half the periodic width (0.02 m)" in message and "one_period=false" in message


def test_wedge_beyond_detachment():
    # theta_max = 36.87 deg at M1 = 3.5 (gamma = 1.4)
    with pytest.raises(InputError) as info:
        partmesh.scene("wedge", theta_deg=40)
    message = one_sentence(info.value)
    assert "theta_deg" in message and "detach" in message


def test_netcdf_file_that_is_not_a_partmesh_result(tmp_path):
    path = tmp_path / "plain.nc"
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_netcdf(path, engine="netcdf4")
    with pytest.raises(SchemaError) as info:
        read(path)
    message = one_sentence(info.value)
    assert "plain.nc" in message and "partmesh" in message


def test_text_file_with_nc_suffix(tmp_path):
    path = tmp_path / "notes.nc"
    path.write_text("not a netCDF file\n")
    with pytest.raises(SchemaError) as info:
        read(path)
    assert "notes.nc" in one_sentence(info.value)


def test_missing_result_file(tmp_path):
    with pytest.raises(FileNotFoundError) as info:
        read(tmp_path / "nowhere.nc")
    assert "nowhere.nc" in one_sentence(info.value)


# --- the command line: exit status 2 and one line on stderr -------------------


def cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "partmesh.cli", *args], check=False, cwd=cwd, capture_output=True, text=True,
                          timeout=300)


@pytest.mark.parametrize("args, names", [
    (("run", "nope", "--method", "fv", "-o", "x.nc"), "nope"),
    pytest.param(("run", "sod", "--method", "nope", "-o", "x.nc"), "nope", marks=pytest.mark.full),
    (("run", "sod", "--method", "fv", "--set", "left_rho=-1", "-o", "x.nc"), "left_rho"),
    pytest.param(("run", "sod", "--method", "fv", "--cfl", "1.5", "-o", "x.nc"), "cfl", marks=pytest.mark.full),
])
def test_cli_bad_input_exits_2_with_one_line(tmp_path, args, names):
    done = cli(*args, cwd=tmp_path)
    assert done.returncode == 2, done.stderr
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("partmesh:") and names in lines[0]
    assert "Traceback" not in done.stderr
    assert not (tmp_path / "x.nc").exists()


def test_cli_compare_of_a_non_result_exits_2(tmp_path):
    (tmp_path / "fake.nc").write_text("hello\n")
    done = cli("compare", "fake.nc", "-o", "rep", cwd=tmp_path)
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("partmesh:") and "fake.nc" in lines[0]


@pytest.mark.parametrize("method, case, dx", [("fv", "sod", 1e-9), ("sph", "sod", 1e-9), ("dsmc", "sod", 1e-8),
                                              ("hybrid", "sod", 1e-9), ("swe", "prins_mound", 1e-9),
                                              ("wcsph", "prins_mound", 1e-6)])
def test_a_run_larger_than_the_free_memory_is_refused_before_it_allocates(method, case, dx):
    from partmesh.cases.memory import available_bytes

    with pytest.raises(InputError) as info:
        partmesh.run(case, method, dx=dx, progress=False)
    message = one_sentence(info.value)
    need, free = (float(v) for v in re.findall(r"about ([0-9.e+]+) GiB .* and ([0-9.e+]+) GiB are free", message)[0])
    assert need > free and free == pytest.approx(available_bytes() / 2**30, rel=0.2)
    assert message.startswith(f"{method} would need") and "raise dx" in message
