"""``partmesh warm`` (:func:`partmesh.warmup.warm`): each method compiled in a process of its own, so the runs
that follow load the compiled code from disk and their timings hold no compile."""

import json
import os
import subprocess
import sys

import pytest

import partmesh as pm
from partmesh.demo import RESOLUTIONS, plan


@pytest.mark.parametrize("processes", [0, -1, 1.5, True, "2"])
def test_a_process_count_that_is_not_a_whole_number_of_at_least_one_is_refused(processes):
    with pytest.raises(pm.InputError, match=r"^processes must be a whole number of at least 1 .*got") as caught:
        pm.warm({"fv": [("sod", {"dx": 1e-2})]}, processes=processes, progress=False)
    assert "\n" not in str(caught.value)


def test_the_demo_plan_starts_the_longest_compile_first_and_holds_every_run():
    runs = plan(("fv", "dsmc", "sph"))
    assert list(runs) == ["sph", "dsmc", "fv"]
    assert all(len(r) == sum(len(dx) for dx in RESOLUTIONS.values()) for r in runs.values())


@pytest.mark.parametrize("args, message", [
    (["sph2"], "partmesh: warm compiles fv, sph, dsmc; got 'sph2'."),
    (["--processes", "0"], "partmesh: processes must be a whole number of at least 1 (or None: the cores); got 0."),
])
def test_the_command_refuses_an_unknown_method_or_no_processes_in_one_line(args, message):
    done = subprocess.run([sys.executable, "-m", "partmesh.cli", "warm", *args], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and done.stderr.strip() == message, done.stderr


WARM_THEN_RUN = """
import json, sys
import partmesh as pm
if sys.argv[1] == "warm":
    print(json.dumps(pm.warm({"fv": [("sod", {"dx": 1 / 157})]}, processes=1, progress=False)))
else:
    print(json.dumps(pm.run("sod", "fv", dx=1 / 157, t_end=0.02, progress=False).attrs["compile_seconds"]))
"""


@pytest.mark.full
def test_a_run_after_warm_in_another_process_loads_its_compiled_step(tmp_path):
    """A grid size no other test runs, in an empty compilation cache: warm compiles it; a later process's
    run at that size loads it, in a fraction of the time."""
    env = {**os.environ, "PARTMESH_JAX_CACHE": str(tmp_path / "jax")}
    warmed = json.loads(subprocess.run([sys.executable, "-c", WARM_THEN_RUN, "warm"], env=env, check=True,
                                       capture_output=True, text=True).stdout.splitlines()[-1])
    compiled = json.loads(subprocess.run([sys.executable, "-c", WARM_THEN_RUN, "run"], env=env, check=True,
                                         capture_output=True, text=True).stdout.splitlines()[-1])
    assert set(warmed) == {"fv", "wall"} and warmed["wall"] >= warmed["fv"] > 0.5
    assert compiled < 0.5 * warmed["fv"], (compiled, warmed)
