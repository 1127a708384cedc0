"""Checkpoint and resume (partmesh.cases.checkpoint; ``partmesh run --checkpoint-every
--resume``): a run stopped by SIGTERM or SIGINT saves its state and its
partial result, and the resumed run ends with the uninterrupted run's
result, bit for bit (fv, dsmc, swe) or to round-off carried by the steps
(sph, wcsph and the particles of hybrid, whose neighbour lists are
searched anew)."""

import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import partmesh
from partmesh.cases.errors import InputError
from partmesh.compare.io import read


def _run_command(case, method, dx, output, extra=()):
    return [sys.executable, "-m", "partmesh.cli", "run", case, "-m", method, "--dx", str(dx), "-o", str(output),
            "--quiet", *extra]


# each run goes on for seconds after its first checkpoint (0.3 s of wall time), so the signal finds it running
@pytest.mark.full
@pytest.mark.parametrize("case, method, dx, extra, settings, stop", [
    ("sod", "fv", 1e-4, (), {}, signal.SIGTERM),
    # a hierarchy: its block lists, maps, registers and step limit are the state
    ("sod", "fv", 1e-4, ("--set", "levels=3"), {"levels": 3}, signal.SIGINT),
    ("sod", "dsmc", 2e-3, ("--set", "ppc=60", "--seed", "4"), {"ppc": 60, "seed": 4}, signal.SIGINT),
    # a hot light driver sets the step; the cold gas ahead is redrawn at its own intervals, held in the checkpoint
    ("sod", "dsmc", 2e-3, ("--set", "ppc=60", "--seed", "4", "--set", "redraw=local", "--set", "left_rho=0.15",
                           "--set", "left_p=1.6"),
     {"ppc": 60, "seed": 4, "redraw": "local", "scene": {"left_rho": 0.15, "left_p": 1.6}}, signal.SIGTERM),
    ("sod", "sph", 2.5e-4, (), {}, signal.SIGTERM),
    ("dam_break", "swe", 1.25e-3, (), {}, signal.SIGINT),
    ("standing_wave", "wcsph", 0.025, ("--t-end", "0.5"), {"t_end": 0.5}, signal.SIGTERM),
    ("sod", "hybrid", 2.5e-3, (), {}, signal.SIGINT),
])
def test_a_stopped_run_resumes_to_the_uninterrupted_result(tmp_path, case, method, dx, extra, settings, stop):
    output = tmp_path / "run.nc"
    checkpoint = tmp_path / "run.nc.checkpoint"
    process = subprocess.Popen(_run_command(case, method, dx, output, (*extra, "--checkpoint-every", "0.3")),
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while not checkpoint.exists() and time.time() < deadline and process.poll() is None:
        time.sleep(0.05)
    process.send_signal(stop)
    _, err = process.communicate(timeout=120)
    assert process.returncode == 3, err  # stopped between steps, with one sentence
    assert f"stopped by {stop.name}" in err and "resume it from" in err
    partial = read(output)
    assert partial.attrs["status"] == "failed" and partial.time.values[-1] < partmesh.scene(case).t_end
    resumed = subprocess.run(_run_command(case, method, dx, output, (*extra, "--resume")), capture_output=True,
                             text=True)
    assert resumed.returncode == 0, resumed.stderr
    assert not checkpoint.exists()  # a complete run leaves no checkpoint behind
    scene = partmesh.scene(case, **settings.get("scene", {}))
    whole = partmesh.run(scene, method, dx=dx, progress=False, **{k: v for k, v in settings.items() if k != "scene"})
    result = read(output)
    assert result.attrs["status"] == "ok" and result.attrs["n_steps"] == whole.attrs["n_steps"]
    for name in whole.data_vars:
        if method == "hybrid":
            # its particles search their neighbours anew too, from a resumed grid that is bit for bit the same
            scale = np.nanmax(np.abs(whole[name].values))
            np.testing.assert_allclose(result[name].values, whole[name].values, rtol=1e-6, atol=1e-6 * scale,
                                       err_msg=name)
        elif method in ("sph", "wcsph"):
            # the resumed run searches its lists anew: the density solve (converged to 1e-8 in H) starts from
            # other brackets, the sums run in another order, and the steps after carry the difference
            # (1.6e-7 measured for sph)
            np.testing.assert_allclose(result[name].values, whole[name].values, rtol=1e-5, atol=1e-5, err_msg=name)
        else:
            np.testing.assert_array_equal(result[name].values, whole[name].values, err_msg=name)


def test_resume_refuses_a_missing_or_foreign_checkpoint(tmp_path):
    scene = partmesh.scene("sod", nx_out=50)
    path = tmp_path / "a.checkpoint"
    with pytest.raises(InputError, match="cannot resume: checkpoint .* does not exist"):
        partmesh.run(scene, "fv", dx=0.02, checkpoint=path, resume=True, progress=False)
    with pytest.raises(InputError, match="resume needs a checkpoint file"):
        partmesh.run(scene, "dsmc", dx=0.02, resume=True, progress=False)
    # a run that checkpoints every step leaves its last state; another setting may not resume from it
    partmesh.run(scene, "fv", dx=0.02, checkpoint=path, checkpoint_every=1e-9, progress=False)
    assert path.exists()
    with pytest.raises(InputError, match="another scene, method or settings"):
        partmesh.run(scene, "fv", dx=0.02, cfl=0.5, checkpoint=path, resume=True, progress=False)
    with pytest.raises(InputError, match="checkpoint_every must be a finite number > 0"):
        partmesh.run(scene, "fv", dx=0.02, checkpoint=path, checkpoint_every=0.0, progress=False)


def test_resume_given_as_text_means_what_it_says(tmp_path):
    """``--option resume=false`` reaches the solver as the text 'false',
    which must start afresh, not resume (any non-empty text is truthy);
    a word that is neither true nor false is refused."""
    scene = partmesh.scene("sod", nx_out=50)
    path = tmp_path / "none_yet.checkpoint"
    fresh = partmesh.run(scene, "fv", dx=0.02, checkpoint=path, resume="false", progress=False)
    assert fresh.attrs["status"] == "ok"
    with pytest.raises(InputError, match="cannot resume: checkpoint .* does not exist"):
        partmesh.run(scene, "fv", dx=0.02, checkpoint=tmp_path / "other.checkpoint", resume="True", progress=False)
    with pytest.raises(InputError, match="resume must be true or false, got 'maybe'"):
        partmesh.run(scene, "fv", dx=0.02, checkpoint=path, resume="maybe", progress=False)
