"""The one time loop of every method (:func:`march`): it advances a run
in stretches of steps through the scene's output times and keeps the
output frames, the probe and side-force history, the progress bar,
checkpoints and stop requests, and a clean stop with the partial result
when a step turns the state non-physical or the time step collapses.

A method supplies the stretch: a callable ``advance(state, t, dt_cfl,
t_out, n_max, dt_floor) -> Stretch`` that takes up to ``n_max`` steps
toward ``t_out`` (the grid methods: a whole stretch in one compiled loop
on the device, :mod:`partmesh.gridref.device_loop`; the particle methods and the
hybrid, which step on the host: one step, :class:`single_steps`). The host sees the state once per stretch;
a stretch is sized to about :data:`STRETCH_SECONDS` of work, so the
progress bar, checkpoints and stop requests are served about once a
second whatever the problem.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass
from typing import Callable

import numpy as np

#: smallest time step, relative to t_end, before a run is declared stalled
DT_FLOOR = 1e-12
#: a step lands on its output time once within this fraction of it
LANDING = 1e-14
#: the wall time a stretch is sized to [s]: the host answers about once a second, and a compiled
#: stretch's fixed cost (on the CPU, its first step touches a fresh scratch buffer: about 60 ms for
#: the 1024² dam break in float64, against 65 ms for each further step) is a few per cent of it
STRETCH_SECONDS = 1.0


@dataclass
class Stretch:
    """What a stretch of steps returns to the host: the state reached, its
    time, its stable step (NaN if the next step turned the state
    non-physical: the state and time are then the last good ones, and
    ``dt_tried`` is the step that failed), the steps taken, and per record
    its end time, probe values and side forces: one record per step, or
    fewer where a method samples its probes at the scene's ``dt_probe``
    (a record then spans the steps since the last one)."""

    state: object
    t: float
    dt_cfl: float
    dt_tried: float
    times: np.ndarray
    probes: np.ndarray
    forces: np.ndarray
    steps: int = -1

    def __post_init__(self):
        if self.steps < 0:
            self.steps = len(self.times)


@dataclass(frozen=True)
class Start:
    """Where a run starts: its ``state`` at time ``t`` and that state's
    stable step ``dt_cfl`` (``inf`` where a method's step finds its own)."""

    state: object
    t: float
    dt_cfl: float = float("inf")


@dataclass(frozen=True)
class Stepping:
    """What a method hands the loop besides its start: ``advance(state, t,
    dt_cfl, t_out, n_max, dt_floor) -> Stretch``, a stretch of steps
    (``advance.n_records`` bounds it); ``saved_state(state, t, dt_cfl)``,
    the dict a checkpoint keeps; and ``diagnose(state, t, step, dt,
    failed)``, the one sentence on when, where and what a failed step ends
    with (None: only a collapsed stable step is told)."""

    advance: Callable
    saved_state: Callable
    diagnose: Callable | None = None


class StepFailed(Exception):
    """Raised by a method's step that cannot go on (an unstable or
    non-physical state it diagnosed itself); the message says when, where
    and what, and :func:`march` stops the run with the result up to the
    last good state."""


def landed(t: float, dt: float, t_out: float) -> float:
    """The time a step of ``dt`` from ``t`` ends at: ``t_out`` once within
    :data:`LANDING` of it (no sliver of a step is left before an output
    time)."""
    return t_out if t + dt >= t_out * (1 - LANDING) else t + dt


def output_times(scene, t_end: float) -> list[float]:
    """The times a run to ``t_end`` keeps a frame at: the scene's output
    times before ``t_end``, then ``t_end``."""
    return [t for t in scene.output.times if t < t_end * (1 - 1e-12)] + [t_end]


class StretchSizer:
    """How many steps the next stretch may take: as many as fit in
    :data:`STRETCH_SECONDS` at the rate the last stretch ran (one at
    first)."""

    def __init__(self, limit: int):
        self.limit, self.n = limit, 1

    def timed(self, seconds: float, steps: int) -> None:
        if steps:
            self.n = int(np.clip(STRETCH_SECONDS * steps / max(seconds, 1e-9), 1, self.limit))


def march(run, start: Start, stepping: Stepping, ckpt, settings):
    """Advance a run from its ``start`` to ``settings.t_end`` in stretches
    of ``stepping.advance`` (see the module docstring), with a progress bar
    unless ``settings.progress`` is False, and return the run's Dataset.

    At every output time the run keeps a frame (``run.output_frame(state)``);
    every stretch's records go to ``run.history``; ``run.state`` and
    ``run.t`` hold the last good state, ``run.totals0`` the conserved
    totals of the first. A step that raises :class:`StepFailed`, turns the
    state non-physical (NaN stable step) or lets the stable step collapse
    below ``DT_FLOOR · t_end`` stops the run:
    :class:`~partmesh.cases.errors.SolverFailed` carries the result up to
    the last good state, with the step's message or ``stepping.diagnose``'s
    sentence (the step ``dt`` made the state non-physical: ``failed``; or
    the stable step collapsed to ``dt``). ``ckpt``
    (:mod:`partmesh.cases.checkpoint`) saves ``stepping.saved_state``
    between stretches.
    """
    state, t, dt_cfl = start.state, start.t, start.dt_cfl
    advance, saved_state = stepping.advance, stepping.saved_state
    diagnose, t_end = stepping.diagnose or _collapsed, settings.t_end
    out_times = output_times(run.scene, t_end)
    bar = run.progress_bar(t, t_end, settings.progress)
    sizer, floor = StretchSizer(advance.n_records), DT_FLOOR * t_end
    run.state, run.t = state, t
    if run.totals0 is None:  # (a resumed run has them from its checkpoint)
        run.totals0 = run.totals(state)
    with ckpt.watching_signals():
        try:
            for t_out in out_times[len(run.frame_times):]:  # (one frame per output time)
                while t < t_out * (1 - LANDING):
                    if not dt_cfl >= floor:  # (NaN too)
                        raise run.failure(diagnose(state, t, run.n_steps, dt_cfl, False), t,
                                          lambda: run.fields(state))
                    started = _time.perf_counter()
                    try:
                        s = advance(state, t, dt_cfl, t_out, sizer.n, floor)
                    except StepFailed as err:
                        raise run.failure(str(err), t, lambda: run.fields(state)) from None
                    sizer.timed(_time.perf_counter() - started, s.steps)
                    if s.steps:
                        run.history.record_steps(run.history.t[-1], s.times, s.probes, s.forces)
                        run.n_steps += s.steps
                        bar.update(s.t - t)
                    state, t, dt_cfl = s.state, s.t, s.dt_cfl
                    run.state, run.t = state, t
                    if not np.isfinite(dt_cfl):
                        # the last good state is kept for the partial result
                        raise run.failure(diagnose(state, t, run.n_steps + 1, s.dt_tried, True), t,
                                          lambda: run.fields(state))
                    bar.set_postfix_str(f"{run.n_steps} steps", refresh=False)
                    ckpt.step_done(run, t, lambda: saved_state(state, t, dt_cfl), lambda: run.fields(state))
                run.add_frame(run.output_frame(state), t)
        finally:
            bar.close()
    return run.dataset()


def _collapsed(state, t, step, dt, failed) -> str:
    """The failure of a method that diagnoses its own steps: only a
    collapsed stable step reaches here."""
    return f"the stable time step collapsed to {dt:.3g} s at t = {t:.6g} s (step {step})."


class single_steps:
    """The stretch of a method that steps on the host: one step of
    ``step(state, t, dt_cfl, t_out) -> (state, dt, dt_next, record)``,
    which takes ``dt`` (at most ``t_out − t``; it ends at :func:`landed`)
    and returns the stable step ``dt_next`` (NaN: the step turned the state
    non-physical and is not taken) and the ``(probes, side_forces)`` at its
    end, or None where it keeps no record."""

    n_records = 1

    def __init__(self, step: Callable):
        self.step = step

    def __call__(self, state, t, dt_cfl, t_out, n_max, dt_floor) -> Stretch:
        new, dt, dt_next, record = self.step(state, t, dt_cfl, t_out)
        if not np.isfinite(dt_next):
            return Stretch(state, t, dt_next, dt, np.zeros(0), np.zeros((0, 0)), np.zeros((0, 0)))
        t_new = landed(t, dt, t_out)
        if record is None:
            return Stretch(new, t_new, dt_next, dt, np.zeros(0), np.zeros((0, 0)), np.zeros((0, 0)), steps=1)
        probes, forces = record
        return Stretch(new, t_new, dt_next, dt, np.array([t_new]), np.asarray(probes, float)[None],
                       np.asarray(forces, float)[None])
