"""The result schema (SPEC §2) and netCDF I/O (SPEC §9: atomic writes,
checked reads) on a real fv run."""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import partmesh
import partmesh.compare.schema
from partmesh.compare.io import read, write
from partmesh.compare.schema import REQUIRED_ATTRS, SchemaError, parameters, validate

SPEC_ATTRS = ("case", "method", "scheme", "dx", "n_elements", "n_steps", "wall_seconds", "compile_seconds",
              "parameters", "partmesh_version", "Conventions", "created")


@pytest.fixture(scope="module")
def scene():
    return partmesh.scene("sod", nx_out=100)


@pytest.fixture(scope="module")
def run_result(scene):
    return partmesh.run(scene, "fv", dx=1e-2, cfl=0.7, limiter="vanleer", riemann="hll", progress=False)


def test_run_result_follows_the_schema(scene, run_result):
    ds = validate(run_result)
    assert set(SPEC_ATTRS) <= set(REQUIRED_ATTRS) <= set(ds.attrs)
    assert ds.attrs["case"] == "sod" and ds.attrs["method"] == "fv"
    assert ds.attrs["Conventions"] == "CF-1.10"
    assert ds.attrs["dx"] == 1e-2 and ds.attrs["n_elements"] == 100
    assert ds.attrs["n_steps"] > 0 and ds.attrs["wall_seconds"] > 0
    assert ds.attrs["status"] == "ok"
    for name, var in ds.variables.items():
        assert var.attrs.get("units"), name
        assert var.attrs.get("long_name"), name
    assert ds["rho"].attrs["units"] == "kg m-3" and ds["p"].attrs["units"] == "Pa"
    assert ds["u"].attrs["units"] == "m s-1" and ds["e"].attrs["units"] == "J kg-1"
    assert ds["time"].attrs["units"] == "s" and ds["x"].attrs["units"] == "m"
    assert ds["rho"].dims == ("time", "x")
    assert ds["p_probe"].dims == ("t_probe", "probe")
    np.testing.assert_allclose(ds.x.values, scene.output.x)
    np.testing.assert_allclose(ds.time.values, scene.output.times)
    # e = p/((γ − 1) rho) for an ideal gas
    np.testing.assert_allclose(ds.e.values, ds.p.values / (0.4 * ds.rho.values), rtol=1e-12)


def test_a_run_names_the_commit_of_the_code_it_ran(run_result):
    """Made from a git checkout (as the README installs it), a result names
    the checkout's commit, read here with git independently of the code."""
    root = Path(partmesh.compare.schema.__file__).resolve().parent.parent
    git = subprocess.run(["git", "-C", str(root), "rev-parse", "--show-toplevel", "HEAD"], capture_output=True,
                         text=True)
    if git.returncode or Path(git.stdout.split()[0]).resolve() != root:
        assert "source_revision" not in run_result.attrs
        return
    commit = git.stdout.split()[1]
    assert run_result.attrs["source_revision"] in (commit, commit + "+dirty")


def test_parameters_repeat_the_run(scene, run_result):
    params = parameters(run_result)
    assert params["scene"] == json.loads(json.dumps(scene.to_dict()))
    assert params["solver"]["method"] == "fv"
    assert params["solver"]["dx"] == 1e-2 and params["solver"]["cfl"] == 0.7
    assert params["solver"]["limiter"] == "vanleer" and params["solver"]["riemann"] == "hll"
    # the scene can be rebuilt from the file alone and is the same scene
    scene_params = dict(params["scene"])
    rebuilt = partmesh.scene(scene_params.pop("case"), **scene_params)
    assert rebuilt.to_dict() == scene.to_dict()


def test_run_records_the_wall_time_it_took_to_reach_each_output_time(run_result):
    seconds = np.asarray(run_result.attrs["frame_seconds"])
    assert seconds.shape == run_result.time.shape
    assert np.all(np.diff(seconds) > 0.0) and 0.0 <= seconds[0] and seconds[-1] <= run_result.attrs["wall_seconds"]


def test_round_trip_through_netcdf(tmp_path, run_result):
    path = write(run_result, tmp_path / "sod.nc")
    assert path.is_file()
    back = read(path)
    assert set(run_result.attrs) <= set(back.attrs)
    for key, value in run_result.attrs.items():
        if isinstance(value, float):
            assert back.attrs[key] == pytest.approx(value, rel=0, abs=0), key
        elif isinstance(value, np.ndarray):
            np.testing.assert_array_equal(back.attrs[key], value, err_msg=key)
        else:
            assert back.attrs[key] == value, key
    assert set(back.variables) == set(run_result.variables)
    for name in run_result.variables:
        np.testing.assert_array_equal(back[name].values, run_result[name].values, err_msg=name)
        assert back[name].attrs["units"] == run_result[name].attrs["units"]
        assert back[name].attrs["long_name"] == run_result[name].attrs["long_name"]
    assert list(back.probe.values) == list(run_result.probe.values)
    assert parameters(back) == parameters(run_result)


def test_write_is_atomic_and_leaves_no_temporary_files(tmp_path, run_result):
    write(run_result, tmp_path / "a.nc")
    write(run_result, tmp_path / "a.nc")  # overwrite in place
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.nc"]


def test_failed_validation_writes_nothing(tmp_path, run_result):
    bad = run_result.copy()
    del bad.attrs["method"]
    with pytest.raises(SchemaError):
        write(bad, tmp_path / "bad.nc")
    assert list(tmp_path.iterdir()) == []


def test_failed_write_keeps_the_previous_file(tmp_path, run_result):
    """A write that fails half way (an attribute netCDF cannot store) leaves
    neither a temporary file nor a damaged target: the old result survives."""
    target = tmp_path / "keep.nc"
    write(run_result, target)
    before = target.read_bytes()
    broken = run_result.copy()
    broken.attrs["unstorable"] = {"a": 1}  # netCDF attributes cannot be dicts
    with pytest.raises((TypeError, ValueError)):
        write(broken, target)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.nc"]
    assert target.read_bytes() == before
    read(target)


@pytest.mark.parametrize("attr", REQUIRED_ATTRS)
def test_validate_refuses_a_missing_attribute(run_result, attr):
    bad = run_result.copy()
    del bad.attrs[attr]
    with pytest.raises(SchemaError, match=attr):
        validate(bad)


def test_validate_refuses_a_field_on_wrong_dims(run_result):
    bad = run_result.copy()
    bad["rho"] = bad["rho"].transpose("x", "time")
    with pytest.raises(SchemaError, match="rho"):
        validate(bad)


def test_validate_refuses_a_variable_without_units(run_result):
    bad = run_result.copy(deep=True)
    del bad["p"].attrs["units"]
    with pytest.raises(SchemaError) as info:
        validate(bad)
    assert "'p'" in str(info.value) and "units" in str(info.value)


def test_validate_refuses_a_variable_without_long_name(run_result):
    bad = run_result.copy(deep=True)
    del bad["x"].attrs["long_name"]
    with pytest.raises(SchemaError, match="long_name"):
        validate(bad)


def test_validate_refuses_unknown_method_and_bad_parameters(run_result):
    bad = run_result.copy()
    bad.attrs["method"] = "magic"
    with pytest.raises(SchemaError, match="magic"):
        validate(bad)
    bad = run_result.copy()
    bad.attrs["parameters"] = "{not json"
    with pytest.raises(SchemaError, match="parameters"):
        validate(bad)


def test_validate_refuses_decreasing_times(run_result):
    bad = run_result.isel(time=[1, 0])
    with pytest.raises(SchemaError, match="time"):
        validate(bad)


def test_validate_refuses_an_unknown_variable(run_result):
    bad = run_result.copy()
    bad["vorticity"] = bad["rho"] * 0
    with pytest.raises(SchemaError, match="vorticity"):
        validate(bad)


def test_validate_refuses_a_non_dataset():
    with pytest.raises(SchemaError):
        validate(xr.DataArray([1.0]))


def test_read_refuses_a_damaged_result(tmp_path, run_result):
    """A file with the partmesh marker but a broken schema is named as such."""
    bad = run_result.copy(deep=True)
    del bad["rho"].attrs["units"]
    path = tmp_path / "damaged.nc"
    bad.to_netcdf(path, engine="netcdf4")
    with pytest.raises(SchemaError) as info:
        read(path)
    assert "damaged.nc" in str(info.value) and "rho" in str(info.value)
