"""The ``partmesh`` command line (SPEC §6), run as a subprocess with the
interpreter running the tests (``python -m partmesh.cli`` is the console
script's ``main``)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
import xarray as xr

import partmesh
import partmesh.compare


def cli(*args, cwd):
    return subprocess.run([sys.executable, "-m", "partmesh.cli", *args], check=False, cwd=cwd, capture_output=True, text=True,
                          timeout=600)


@pytest.fixture(scope="module")
def workdir(tmp_path_factory):
    return tmp_path_factory.mktemp("cli")


@pytest.fixture(scope="module")
def sod_file(workdir):
    done = cli("run", "sod", "--method", "fv", "--dx", "5e-3", "-o", "tmp/sod.nc", "--quiet", cwd=workdir)
    assert done.returncode == 0, done.stderr
    assert done.stdout == ""  # --quiet
    return workdir / "tmp" / "sod.nc"


@pytest.fixture(scope="module")
def sedov_file(workdir):
    done = cli("run", "sedov", "--method", "fv", "--set", "n_out=32", "--set", "E=2", "--dx", "0.0625",
               "--t-end", "0.05", "-o", "tmp/sedov.nc", "--quiet", cwd=workdir)
    assert done.returncode == 0, done.stderr
    return workdir / "tmp" / "sedov.nc"


def test_run_writes_a_result_file(sod_file):
    with xr.open_dataset(sod_file, engine="netcdf4") as ds:
        assert ds.attrs["case"] == "sod" and ds.attrs["method"] == "fv"
        assert ds.attrs["dx"] == 5e-3
        assert ds.sizes["x"] == 400  # the scene's output grid, not the 200 solver cells
        assert ds.attrs["status"] == "ok"
    assert sorted(p.name for p in sod_file.parent.iterdir() if p.name.startswith(".")) == []


@pytest.mark.full
def test_run_passes_scene_settings(sedov_file):
    with xr.open_dataset(sedov_file, engine="netcdf4") as ds:
        params = json.loads(ds.attrs["parameters"])
        assert params["scene"]["n_out"] == 32 and params["scene"]["E"] == 2.0
        assert params["solver"]["t_end"] == pytest.approx(0.05)
        assert float(ds.time[-1]) == pytest.approx(0.05)
        assert ds.sizes["x"] == ds.sizes["y"] == 32


def test_compare_against_exact_writes_the_independent_error(workdir, sod_file):
    done = cli("compare", "tmp/sod.nc", "-o", "tmp/rep", cwd=workdir)
    assert done.returncode == 0, done.stderr
    rep = workdir / "tmp" / "rep"
    assert (rep / "summary.csv").is_file() and (rep / "summary.json").is_file()
    rows = json.loads((rep / "summary.json").read_text())
    assert len(rows) == 1
    csv = pd.read_csv(rep / "summary.csv")
    assert len(csv) == 1
    # the error computed here from the file and the scene's exact solution:
    # L1 = mean |rho − rho_exact| on the uniform output grid at the last time
    with xr.open_dataset(sod_file, engine="netcdf4") as ds:
        t = float(ds.time[-1])
        rho = ds.rho.isel(time=-1).values
        x = ds.x.values
    reference = partmesh.scene("sod").exact([t])
    np.testing.assert_allclose(reference.x.values, x, rtol=0, atol=1e-14)
    expected = float(np.mean(np.abs(rho - reference.rho.isel(time=0).values)))
    assert 1e-4 < expected < 1e-2
    assert rows[0]["rho_L1"] == pytest.approx(expected, rel=1e-9)
    assert csv["rho_L1"].iloc[0] == pytest.approx(expected, rel=1e-9)
    assert rows[0]["method"] == "fv"
    with xr.open_dataset(rep / "summary.nc") as table:  # the table as a Dataset on 'run'
        assert table["rho_L1"].values[0] == pytest.approx(expected, rel=1e-9) and str(table["method"].values[0]) == "fv"


@pytest.mark.full
def test_compare_a_2d_point_blast_against_its_exact_solution(workdir, sedov_file):
    # the scene's output times start at t = 0, where a point blast has no similarity solution: compared at 0.05
    done = cli("compare", "tmp/sedov.nc", "-o", "tmp/rep_sedov", cwd=workdir)
    assert done.returncode == 0, done.stderr
    rows = json.loads((workdir / "tmp" / "rep_sedov" / "summary.json").read_text())
    with xr.open_dataset(sedov_file, engine="netcdf4") as ds:
        rho = ds.rho.isel(time=-1).values
    exact = partmesh.scene("sedov", n_out=32, E=2.0, t_end=0.05).exact([0.05]).rho.isel(time=0).values
    assert rows[0]["error_time"] == pytest.approx(0.05)
    assert rows[0]["rho_L1"] == pytest.approx(float(np.mean(np.abs(rho - exact))), rel=1e-9)


@pytest.mark.full
def test_compare_against_a_reference_file(workdir, sod_file):
    done = cli("compare", "tmp/sod.nc", "--reference", "tmp/sod.nc", "-o", "tmp/rep_self", cwd=workdir)
    assert done.returncode == 0, done.stderr
    rows = json.loads((workdir / "tmp" / "rep_self" / "summary.json").read_text())
    assert rows[0]["rho_L1"] == 0.0


@pytest.mark.full
def test_compare_refuses_runs_of_different_scenes(workdir, sod_file, sedov_file):
    done = cli("compare", "tmp/sod.nc", "tmp/sedov.nc", "-o", "tmp/rep_mixed", cwd=workdir)
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("partmesh:") and "different scene" in lines[0]
    assert "Traceback" not in done.stderr


def test_cases_lists_every_scene(tmp_path):
    done = cli("cases", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    listed = {line.split(":")[0] for line in done.stdout.splitlines() if line and not line.startswith(" ")}
    assert set(partmesh.scenes()) <= listed
    for name in ("sod", "shock_reflection", "wedge", "sedov", "noh", "blast_wall", "cylinder_shock"):
        assert name in listed
    assert "left_rho" in done.stdout and "theta_deg" in done.stdout  # parameters are listed too


@pytest.mark.full
def test_solver_options_from_the_command_line_arrive_as_numbers(tmp_path):
    # --option values are strings on the command line; the solvers must use the validated numbers
    out = tmp_path / "sod_opt.nc"
    proc = subprocess.run([sys.executable, "-m", "partmesh.cli", "run", "sod", "--method", "fv", "--dx", "5e-3",
                           "--option", "cfl=0.4", "--option", "limiter=minmod", "-o", str(out), "--quiet"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    solver = json.loads(partmesh.read(out).attrs["parameters"])["solver"]
    assert solver["cfl"] == 0.4 and solver["limiter"] == "minmod"
