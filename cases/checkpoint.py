"""Checkpoints and clean interruption of long runs (SPEC §6, §9).

A solver that takes a :class:`Checkpoint` saves its whole state between two
steps every ``every`` seconds of wall time, and when the run receives
SIGINT or SIGTERM: the signal only raises a flag, the step under way ends,
the state is saved, and the run stops with its partial result
(``status = "failed"``). A later run of the same scene, method and settings
with ``resume=True`` starts from the saved state; the solvers restore
everything a step depends on, so the resumed run ends with the result an
uninterrupted one gives: bit for bit for fv and dsmc (with its seed), to
~1e-7 for sph, which searches its neighbour lists anew (its density solve,
converged to 1e-8, then starts from other brackets).

Python delivers a signal to a process's main thread, and a Dask worker runs
its task in another one; so the request to stop is a flag of the process,
which every run in it reads between two steps. A worker of a sweep's
cluster installs the handlers once (:func:`watch_signals_for_runs`), and
the sweep, stopped by a signal of its own, asks every worker to stop
(:func:`request_stop`).

The file is a pickle of numpy arrays and plain values, written atomically
(a temporary file renamed), tagged with the run's identity: the package
version, scene parameters, method and settings, which must match to resume.
"""

from __future__ import annotations

import os
import pickle
import signal
import tempfile
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from partmesh.cases.checks import flag, positive
from partmesh.cases.errors import InputError
from partmesh.compare.schema import version

#: the layout of a checkpoint's state: a checkpoint of another layout is refused, not half-read
#: (2: the run record keeps the initial totals and, for dsmc, the moments of the frame under way)
FORMAT = 2

#: the signals that stop a run cleanly
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)

_stop_request: list[str] = []  # the name of the signal that asked every run of this process to stop


def request_stop(name: str = "SIGTERM") -> None:
    """Ask every run of this process to stop after its step under way,
    saving its state and its partial result (``name``: the signal that
    asked)."""
    if not _stop_request:
        _stop_request.append(name)


def stop_requested() -> str | None:
    """The name of the signal that asked this process's runs to stop, or None."""
    return _stop_request[0] if _stop_request else None


def clear_stop_request() -> None:
    """Let this process's next runs go on (after a stop was handled)."""
    _stop_request.clear()


def _ask_to_stop(number, frame) -> None:
    request_stop(signal.Signals(number).name)


def _handled_by(handler) -> dict:
    """Make ``handler`` the handler of the stop signals; returns the ones it replaced."""
    return {s: signal.signal(s, handler) for s in STOP_SIGNALS}


def _restore(previous: dict) -> None:
    """Put back the handlers :func:`_handled_by` replaced."""
    for s, handler in previous.items():
        signal.signal(s, handler)


def watch_signals_for_runs() -> bool:
    """From now on, SIGINT and SIGTERM ask this process's runs to stop
    instead of ending the process; for the main thread of a worker process
    whose runs go on in other threads. Returns whether the handlers were
    installed (only a main thread can)."""
    if threading.current_thread() is not threading.main_thread():
        return False
    _handled_by(_ask_to_stop)
    return True


class Interrupted(Exception):
    """A SIGINT or SIGTERM that arrived while this process waited for runs
    going on elsewhere; ``signal`` is its name."""
    def __init__(self, name: str):
        super().__init__(f"stopped by {name}")
        self.signal = name


@contextmanager
def signals_raised():
    """Inside, in a main thread: SIGINT and SIGTERM raise :class:`Interrupted`
    (then the previous handlers are back, so a second Ctrl-C acts at once);
    in another thread nothing changes."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(number, frame):
        _restore(previous)
        raise Interrupted(signal.Signals(number).name)

    previous = _handled_by(interrupt)
    try:
        yield
    finally:
        _restore(previous)


class Checkpoint:
    """The checkpoint file of one run (``path`` None: none is written, but
    SIGINT/SIGTERM still stop the run cleanly between steps)."""
    def __init__(self, path=None, every: float = 600.0, resume: bool = False, identity: dict | None = None):
        self.path = Path(path) if path is not None else None
        self.every = positive("checkpoint_every", every)
        self.resume, self.identity = flag("resume", resume), identity or {}
        if self.resume and self.path is None:
            raise InputError("resume needs a checkpoint file (checkpoint=PATH, or --checkpoint-every with -o).")
        self._last = time.perf_counter()

    @property
    def stop(self) -> str | None:
        """The name of the signal that asked the run to stop, or None."""
        return stop_requested()

    def saved_state(self, run):
        """The solver state saved by an earlier run with the same identity,
        with the run's record (a :class:`partmesh.cases.history.RunRecord`) restored
        from it; None if not resuming. Refuses a missing file or another
        run's."""
        if not self.resume:
            return None
        if not self.path.is_file():
            raise InputError(f"cannot resume: checkpoint {str(self.path)!r} does not exist.")
        with open(self.path, "rb") as f:
            saved = pickle.load(f)
        if saved.get("identity") != self.identity:
            raise InputError(f"cannot resume: checkpoint {str(self.path)!r} was written by a run of another scene, "
                             f"method or settings; remove it to start the run afresh.")
        run.restore(saved["state"]["run"])
        return saved["state"]

    def step_done(self, run, t: float, state, frame) -> None:
        """Between two steps, at time ``t``: save the solver's ``state()``
        (a dict) with the run's record when due; after a signal, stop the
        run with its partial result (``frame()``: the fields at ``t``)."""
        if not self.due():
            return
        self.save({**state(), "run": run.saved()})
        if self.stop is not None:
            where = f"; resume it from {str(self.path)!r}" if self.path is not None else ""
            raise run.failure(f"{run.method} run of {run.scene.name} stopped by {self.stop} at t = {t:.6g} s after "
                              f"{run.n_steps} steps{where}.", t, frame)

    def due(self) -> bool:
        """Whether to save now: a signal arrived, or ``every`` seconds passed."""
        return self.stop is not None or (self.path is not None and time.perf_counter() - self._last >= self.every)

    def save(self, state: dict) -> None:
        """Write ``state`` atomically (nothing without a path)."""
        self._last = time.perf_counter()
        if self.path is None:
            return
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{self.path.name}.", suffix=".tmp", dir=self.path.parent)
        try:
            with os.fdopen(fd, "wb") as f:
                pickle.dump({"identity": self.identity, "state": state}, f, protocol=pickle.HIGHEST_PROTOCOL)
            os.replace(tmp, self.path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)

    @contextmanager
    def watching_signals(self):
        """SIGINT and SIGTERM set :attr:`stop` instead of killing the run
        (a main thread installs the handlers for the run and clears the
        request after it; another thread relies on its process's handlers,
        :func:`watch_signals_for_runs`)."""
        if threading.current_thread() is not threading.main_thread():
            yield self
            return
        previous = _handled_by(_ask_to_stop)
        try:
            yield self
        finally:
            _restore(previous)
            clear_stop_request()


def checkpoint_for(scene, settings) -> Checkpoint:
    """The :class:`Checkpoint` of a run of ``scene`` with ``settings`` (a
    :class:`~partmesh.cases.settings.Settings`): its file, period and resume flag,
    and the run's identity (scene, method, the settings it computes with)."""
    identity = {"version": version(), "format": FORMAT, "scene": scene.to_dict(), "method": settings.method,
                "settings": settings.record()}
    return Checkpoint(settings.checkpoint, settings.checkpoint_every, settings.resume, identity)
