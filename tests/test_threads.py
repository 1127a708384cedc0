"""The numba threads of particle runs: one thread for small runs, idle OpenMP threads that sleep rather
than spin (``OMP_WAIT_POLICY=PASSIVE``) unless the user chose otherwise, set before any thread starts, and
kernels whose only parallel loops are their ``prange`` loops."""

import ast
import os
import subprocess
import sys
from pathlib import Path

import numba
import pytest

from partmesh.particle.threads import SERIAL_BELOW, WAIT_POLICY, threads_for

POLICY_AT_FIRST_LOOP = """
import os
import partmesh
before = os.environ.get("OMP_WAIT_POLICY")
partmesh.run("sod", "dsmc", dx=0.02, t_end=0.01, progress=False)
print(before, os.environ.get("OMP_WAIT_POLICY"))
"""


@pytest.mark.parametrize("chosen", [None, "ACTIVE"])
def test_the_wait_policy_is_passive_from_the_first_parallel_loop_unless_the_user_set_one(chosen):
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    if chosen:
        env["OMP_WAIT_POLICY"] = chosen
    out = subprocess.run([sys.executable, "-c", POLICY_AT_FIRST_LOOP], env=env, capture_output=True, text=True,
                         check=True).stdout.split()
    assert len(out) == 2
    # importing partmesh alone sets nothing (the particle package does, on the run's first use of it)
    assert out == [str(chosen), chosen or WAIT_POLICY]


def test_small_runs_use_one_thread_and_the_setting_comes_back():
    before = numba.get_num_threads()
    with threads_for(SERIAL_BELOW - 1):
        assert numba.get_num_threads() == 1
    with threads_for(SERIAL_BELOW):
        assert numba.get_num_threads() == before
    assert numba.get_num_threads() == before


def _parallel_kernels():
    """(file:line name, its ``parallel=`` source, whether it has a ``prange`` loop) of every numba kernel of
    ``particle/`` that asks for threads, read from the source."""
    for path in sorted((Path(__file__).resolve().parents[1] / "particle").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.FunctionDef):
                continue
            for deco in node.decorator_list:
                option = next((k.value for k in getattr(deco, "keywords", ()) if k.arg == "parallel"), None)
                if option is not None:
                    loops = [f for f in ast.walk(node) if isinstance(f, ast.For) and "prange" in ast.unparse(f.iter)]
                    yield f"{path.name}:{node.lineno} {node.name}", ast.unparse(option), bool(loops)


def test_particle_kernels_thread_only_their_prange_loops():
    kernels = list(_parallel_kernels())
    assert len(kernels) > 30  # the checker sees the kernels it judges
    assert [k for k, option, _ in kernels if option != "PRANGE_ONLY"] == []
    assert [k for k, _, has_loop in kernels if not has_loop] == []
