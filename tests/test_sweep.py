"""Sweeps on Dask (partmesh.sweeps, ``partmesh sweep``): the product of runs,
one file per run, a killed sweep finished by running it again, a stopped
one saving its runs under way and resuming them, failures reported without
losing the finished runs, the runs opened together."""

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import partmesh
from partmesh.cases.errors import InputError
from partmesh.compare.io import read
from partmesh.sweeps import finished, open_sweep, plan, sweep


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
    return [sys.executable, "-m", "partmesh.cli", "sweep", "sod", "-m", "dsmc", "--dx", "0.01,0.0125",
            "--set", "x0=0.4,0.5", "--set", "ppc=150,200,250", "--seed", "1", "--workers", "2", "--quiet",
            "-o", str(folder)]


@pytest.mark.full
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


def _stoppable_command(folder):
    # fv at 5e-5 (20 000 cells, about 11 000 steps: some 15 s in stretches of about 1 s) first, then a run of
    # 0.5 s; one worker, a checkpoint every 0.3 s
    return [sys.executable, "-m", "partmesh.cli", "sweep", "sod", "-m", "fv", "--dx", "5e-5,1e-3", "--workers", "1",
            "--option", "checkpoint_every=0.3", "--quiet", "-o", str(folder)]


def _stopped(folder, send, after_ns=0):
    """Run the sweep until the long run saves its state (after ``after_ns``), stop it with ``send(process)``;
    return its stderr."""
    checkpoint = folder / "sod_fv_dx5e-05.nc.checkpoint"
    process = subprocess.Popen(_stoppable_command(folder), start_new_session=True, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 180
    while (not checkpoint.exists() or checkpoint.stat().st_mtime_ns <= after_ns) and time.time() < deadline \
            and process.poll() is None:
        time.sleep(0.05)
    send(process)
    _, err = process.communicate(timeout=180)
    assert process.returncode == 3, err
    return err


def _to_the_worker(process, stop):
    """Send ``stop`` to the sweep's worker process alone."""
    import psutil

    workers = [c for c in psutil.Process(process.pid).children() if "spawn_main" in " ".join(c.cmdline())]
    assert len(workers) == 1
    workers[0].send_signal(stop)


@pytest.mark.full
def test_a_stopped_sweep_saves_its_runs_under_way_and_resumes_them(tmp_path):
    """SIGTERM to the sweep alone (a batch system's kill), to its worker alone, then Ctrl-C (SIGINT to the sweep
    and its worker): each time the run under way ends its step, writes its partial result and its state, and
    the other run does not begin; run again, the sweep resumes from the state and ends with the uninterrupted
    result, bit for bit."""
    folder = tmp_path / "runs"
    long, short = folder / "sod_fv_dx5e-05.nc", folder / "sod_fv_dx0.001.nc"
    checkpoint = folder / "sod_fv_dx5e-05.nc.checkpoint"
    reached = []
    for send, by, name in ((lambda p: p.send_signal(signal.SIGTERM), "SIGTERM", "SIGTERM"),
                           (lambda p: _to_the_worker(p, signal.SIGTERM), "a signal to its workers", "SIGTERM"),
                           (lambda p: os.killpg(p.pid, signal.SIGINT), "SIGINT", "SIGINT")):
        err = _stopped(folder, send, checkpoint.stat().st_mtime_ns if checkpoint.exists() else 0)
        assert f"sweep sod stopped by {by}: 0 runs finished, 1 ended early" in err and "1 not begun" in err, err
        partial = read(long)
        assert partial.attrs["status"] == "failed" and f"stopped by {name}" in partial.attrs["failure"]
        assert checkpoint.exists() and not short.exists()
        reached.append(float(partial.time.values[-1]))
    assert 0 < reached[0] < reached[1] < reached[2] < 0.2  # each stop came later: the run resumed and went on
    again = subprocess.run(_stoppable_command(folder), capture_output=True, text=True)
    assert again.returncode == 0 and "2 runs of sod: 2 ran" in again.stdout, again.stderr
    assert finished(long) and finished(short) and not checkpoint.exists()
    whole, result = partmesh.run("sod", "fv", dx=5e-5, progress=False), read(long)
    assert result.attrs["n_steps"] == whole.attrs["n_steps"]
    for name in whole.data_vars:
        np.testing.assert_array_equal(result[name].values, whole[name].values, err_msg=name)


def test_a_sweep_sets_each_runs_checkpoint_itself():
    with pytest.raises(InputError, match="checkpoint is not a setting of a sweep: each run saves its state to "
                                         "<its file>.checkpoint"):
        sweep("sod", ["fv"], [0.02], output="unused", settings={"checkpoint": "a.checkpoint"}, progress=False)


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
