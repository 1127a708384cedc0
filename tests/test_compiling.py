"""While a method compiles, the terminal says so (issue: a first run's
minute of silence): ``compiling <method> kernels (first run only)`` with
the seconds so far, cleared before the run's progress bar starts; the
seconds become the result's ``compile_seconds``. And what it compiles, it
compiles once: each particle kernel for one signature."""

import io
import os
import subprocess
import sys
import time

import pytest

import partmesh as pm
from partmesh.cases.compiling import REDRAW, compiling


class Terminal(io.StringIO):
    """Standard error as a terminal would take it."""

    def isatty(self):
        return True


def test_the_line_names_the_method_counts_its_seconds_and_is_cleared():
    terminal = Terminal()
    with compiling("sph", file=terminal) as compiled:
        time.sleep(1.0 + 2.5 * REDRAW)
    shown = terminal.getvalue().split("\r")
    lines = [s for s in shown if s.strip()]
    assert lines[0] == "compiling sph kernels (first run only) [00:00]"
    assert "compiling sph kernels (first run only) [00:01]" in lines  # (redrawn while it lasted)
    assert shown[-1] == "" and shown[-2].strip() == ""  # (cleared at the end)
    assert 1.0 + 2.5 * REDRAW <= compiled.seconds < 1.5 + 2.5 * REDRAW


@pytest.mark.parametrize("progress, terminal", [(False, True), (True, False)])
def test_nothing_is_shown_without_progress_or_off_a_terminal(progress, terminal):
    out = Terminal() if terminal else io.StringIO()
    with compiling("fv", progress, file=out) as compiled:
        time.sleep(0.01)
    assert out.getvalue() == "" and compiled.seconds >= 0.01


@pytest.mark.parametrize("method, dx, when", [("fv", 1e-2, "first run at this grid size only"),
                                              ("dsmc", 2e-2, "first run only")])
def test_a_run_says_it_compiles_before_its_progress_bar(monkeypatch, method, dx, when):
    terminal = Terminal()
    monkeypatch.setattr(sys, "stderr", terminal)
    ds = pm.run("sod", method, dx=dx, t_end=0.01, progress=True)
    shown = terminal.getvalue()
    line = f"compiling {method} kernels ({when})"
    assert line in shown and f"{method} sod:" in shown
    assert shown.index(line) < shown.index(f"{method} sod:")
    assert ds.attrs["compile_seconds"] > 0.0


#: short sod runs of the particle methods in a fresh numba cache; prints every partmesh kernel compiled for more
#: than one signature
_SIGNATURES = """
import gc
from numba.core.registry import CPUDispatcher
import partmesh as pm
for method in ("sph", "dsmc"):
    pm.run("sod", method, dx=0.01, t_end=0.02 * pm.scene("sod").t_end, progress=False)
for d in gc.get_objects():
    if isinstance(d, CPUDispatcher) and d.py_func.__module__.startswith("partmesh") and len(d.overloads) > 1:
        print(d.py_func.__module__, d.py_func.__qualname__, *map(str, d.overloads))
"""


@pytest.mark.full
def test_a_run_compiles_each_particle_kernel_for_one_signature(tmp_path):
    """Every kernel of a short sph and dsmc run compiles once: a helper that
    a prange loop calls with its unsigned index and other code with an int64
    compiled twice (3 to 4 s each)."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    done = subprocess.run([sys.executable, "-c", _SIGNATURES], env=env, check=True, capture_output=True, text=True)
    assert done.stdout == ""
