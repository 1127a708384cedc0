"""Sweeps on Dask (cases.sweep, ``partmesh sweep``): the product of runs,
one file per run, a killed sweep finished by running it again, failures
reported without losing the finished runs, the runs opened together."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from cases.errors import InputError
from cases.sweep import finished, open_sweep, plan, sweep


def test_plan_is_the_product_with_each_setting_sweeping_the_methods_that_take_it():
    runs = plan("sod", ["fv", "dsmc"], [0.02, 0.01], {"x0": [0.4, 0.5], "ppc": [5, 10, 20]})
    fv = [r for r in runs if r.method == "fv"]
    dsmc = [r for r in runs if r.method == "dsmc"]
    assert len(fv) == 2 * 2 and len(dsmc) == 2 * 2 * 3  # ppc is no setting of fv: it runs once per (dx, x0)
    assert len({r.name for r in runs}) == len(runs)
    assert dsmc[0].name == "sod_dsmc_dx0.02_x0-0.4_ppc-5" and fv[-1].name == "sod_fv_dx0.01_x0-0.5"
    with pytest.raises(InputError, match="'bogus' is neither a parameter of scene sod nor a setting of fv"):
        plan("sod", ["fv"], values={"bogus": [1]})
    with pytest.raises(InputError, match="unknown method 'wat'"):
        plan("sod", ["wat"])
    with pytest.raises(InputError, match="x0 needs at least one value"):
        plan("sod", ["fv"], values={"x0": []})


def _command(folder):
    # 12 runs: dsmc at 2 spacings x 2 interfaces x 3 particle counts, ~ 0.5-1 s each
    return [sys.executable, "-m", "cases.cli", "sweep", "sod", "-m", "dsmc", "--dx", "0.01,0.0125",
            "--set", "x0=0.4,0.5", "--set", "ppc=150,200,250", "--seed", "1", "--workers", "2", "--quiet",
            "-o", str(folder)]


def test_a_killed_sweep_is_finished_by_running_it_again(tmp_path):
    folder = tmp_path / "runs"
    process = subprocess.Popen(_command(folder), start_new_session=True, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    deadline = time.time() + 300
    done = []
    while time.time() < deadline and len(done) < 4:
        time.sleep(0.2)
        done = [p for p in folder.glob("*.nc") if finished(p)] if folder.exists() else []
    os.killpg(process.pid, signal.SIGKILL)  # the sweep and its workers, half-way
    process.wait()
    done = {p.name: p.stat().st_mtime_ns for p in folder.glob("*.nc") if finished(p)}
    assert 4 <= len(done) < 12
    records = sweep("sod", ["dsmc"], [0.01, 0.0125], {"x0": ["0.4", "0.5"], "ppc": ["150", "200", "250"]},
                    folder, {"seed": 1}, workers=2, progress=False)
    assert len(records) == 12 and all(finished(r["path"]) for r in records)
    ran = {os.path.basename(r["path"]) for r in records if r["status"] == "ran"}
    skipped = {os.path.basename(r["path"]) for r in records if r["status"] == "done before"}
    assert skipped == set(done) and ran.isdisjoint(done) and len(ran) == 12 - len(done)
    assert {p: os.stat(folder / p).st_mtime_ns for p in done} == done  # the finished files were left alone
    # the runs open together, each labelled with its own parameters
    ds = open_sweep(folder)
    assert ds.sizes["run"] == 12
    x0 = ds["x0"].values.astype(float)
    mass = ds["rho"].isel(time=-1).mean("x").values
    np.testing.assert_allclose(mass, x0 + (1 - x0) * 0.125, rtol=0.03)  # mass stays where x0 put it


def test_failed_runs_are_reported_and_the_others_kept(tmp_path, monkeypatch):
    records = sweep("sod", ["fv", "dsmc"], [0.02], {"cfl": [0.5, 2.0]}, tmp_path, {"t_end": 0.05},
                    workers=2, progress=False)
    status = {r["name"]: r["status"] for r in records}
    assert status == {"sod_fv_dx0.02_cfl-0.5": "ran", "sod_fv_dx0.02_cfl-2.0": "failed",
                      "sod_dsmc_dx0.02_cfl-0.5": "ran", "sod_dsmc_dx0.02_cfl-2.0": "failed"}
    failed = [r for r in records if r["status"] == "failed"]
    assert all("cfl must lie in (0, 1]" in r["message"] for r in failed)
    assert sorted(p.name for p in tmp_path.glob("*.nc")) == ["sod_dsmc_dx0.02_cfl-0.5.nc", "sod_fv_dx0.02_cfl-0.5.nc"]
    # fv conserves mass to round-off: the mean density of the sod tube at t = 0.05 (waves inside)
    monkeypatch.chdir(tmp_path)
    ds = open_sweep(".")  # a relative folder
    fv = ds.where(ds["method"] == "fv", drop=True)
    np.testing.assert_allclose(fv["rho"].isel(time=-1).mean("x").values, 0.5625, rtol=1e-12)
