"""While a method compiles, the terminal says so (issue: a first run's
minute of silence): ``compiling <method> kernels (first run only)`` with
the seconds so far, cleared before the run's progress bar starts; the
seconds become the result's ``compile_seconds``."""

import io
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
