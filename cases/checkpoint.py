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

from cases.checks import flag, positive
from cases.errors import InputError

#: settings that say where and how often to checkpoint, not what the run computes
CHECKPOINT_SETTINGS = ("checkpoint", "checkpoint_every", "resume")


class Checkpoint:
    """The checkpoint file of one run (``path`` None: none is written, but
    SIGINT/SIGTERM still stop the run cleanly between steps)."""

    def __init__(self, path=None, every: float = 600.0, resume: bool = False, identity: dict | None = None):
        self.path = Path(path) if path is not None else None
        self.every = positive("checkpoint_every", every)
        self.resume, self.identity = flag("resume", resume), identity or {}
        if self.resume and self.path is None:
            raise InputError("resume needs a checkpoint file (checkpoint=PATH, or --checkpoint-every with -o).")
        self.stop = None  # the name of the signal that asked the run to stop
        self._last = time.perf_counter()

    def saved_state(self, run):
        """The solver state saved by an earlier run with the same identity,
        with the run's record (a :class:`cases.history.RunRecord`) restored
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
                             f"method or settings.")
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
        (only in the main thread, where Python delivers signals)."""
        if threading.current_thread() is not threading.main_thread():
            yield self
            return

        def ask_to_stop(number, frame):
            self.stop = signal.Signals(number).name

        previous = {s: signal.signal(s, ask_to_stop) for s in (signal.SIGINT, signal.SIGTERM)}
        try:
            yield self
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)


def checkpoint_for(scene, method: str, settings: dict, checkpoint=None, checkpoint_every=600.0,
                   resume=False) -> Checkpoint:
    """The :class:`Checkpoint` of a run of ``scene`` with ``method`` and
    ``settings`` (its identity)."""
    from compare.schema import version

    identity = {"version": version(), "scene": scene.to_dict(), "method": method, "settings": settings}
    return Checkpoint(checkpoint, checkpoint_every, resume, identity)
