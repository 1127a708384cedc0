"""The one time loop of every method (:func:`march`): it advances a run
in stretches of steps through the scene's output times and keeps the
output frames, the probe and side-force history, the progress bar,
checkpoints and stop requests, and a clean stop with the partial result
when a step turns the state non-physical or the time step collapses.

A method supplies the stretch: a callable ``advance(state, t, dt_cfl,
t_out, n_max, dt_floor) -> Stretch`` that takes up to ``n_max`` steps
toward ``t_out`` (the grid methods: a whole stretch in one compiled loop
on the device, :mod:`gridref.device_loop`; a method that steps on the host:
one step, :func:`single_steps`). The host sees the state once per stretch;
a stretch is sized to about :data:`STRETCH_SECONDS` of work, so the
progress bar, checkpoints and stop requests are served a few times a
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
#: the wall time a stretch is sized to, so the host answers a few times a second [s]
STRETCH_SECONDS = 0.25


@dataclass
class Stretch:
    """What a stretch of steps returns to the host: the state reached, its
    time, its CFL step (NaN if the next step turned the state non-physical:
    the state and time are then the last good ones, and ``dt_tried`` is the
    step that failed), and per step taken its end time, probe values and
    side forces."""

    state: object
    t: float
    dt_cfl: float
    dt_tried: float
    times: np.ndarray
    probes: np.ndarray
    forces: np.ndarray

    @property
    def steps(self) -> int:
        return len(self.times)


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


def march(run, state, t: float, dt_cfl: float, t_end: float, advance: Callable, diagnose, ckpt, bar,
          saved_state):
    """Advance ``state`` from ``t`` to ``t_end`` in stretches of
    ``advance`` (see the module docstring; ``advance.n_records`` bounds a
    stretch) and return the run's Dataset.

    At every output time the run keeps a frame (``run.fields(state)``);
    every stretch's steps go to ``run.history``. ``diagnose(state, t, step,
    dt, failed) -> str`` says in one sentence when, where and what went
    wrong after the good ``state`` at ``t``: the step ``dt`` made it
    non-physical (``failed``), or the CFL step collapsed to ``dt``; a non-physical step or a collapsed time step
    raises :class:`~cases.errors.SolverFailed` carrying the result up to
    the last good state. ``ckpt`` (:mod:`cases.checkpoint`) saves
    ``saved_state(state, t, dt_cfl)`` (a dict) between stretches; ``bar``
    shows the progress.
    """
    out_times = output_times(run.scene, t_end)
    sizer, floor = StretchSizer(advance.n_records), DT_FLOOR * t_end
    with ckpt.watching_signals():
        try:
            for t_out in out_times[len(run.frame_times):]:  # (one frame per output time)
                while t < t_out * (1 - LANDING):
                    if not np.isfinite(dt_cfl) or dt_cfl < floor:
                        raise run.failure(diagnose(state, t, run.n_steps, dt_cfl, False), t,
                                          lambda: run.fields(state))
                    started = _time.perf_counter()
                    s = advance(state, t, dt_cfl, t_out, sizer.n, floor)
                    sizer.timed(_time.perf_counter() - started, s.steps)
                    if s.steps:
                        run.history.record_steps(t, s.times, s.probes, s.forces)
                        run.n_steps += s.steps
                        bar.update(s.t - t)
                    state, t, dt_cfl = s.state, s.t, s.dt_cfl
                    if not np.isfinite(dt_cfl):
                        # the last good state is kept for the partial result
                        raise run.failure(diagnose(state, t, run.n_steps + 1, s.dt_tried, True), t,
                                          lambda: run.fields(state))
                    bar.set_postfix_str(f"{run.n_steps} steps", refresh=False)
                    ckpt.step_done(run, t, lambda: saved_state(state, t, dt_cfl), lambda: run.fields(state))
                run.add_frame(run.fields(state), t)
        finally:
            bar.close()
    return run.dataset()


class single_steps:
    """The stretch of a method that steps on the host: one step of
    ``step(state, t, dt) -> (state, dt_next, probes, side_forces)`` (NaN
    ``dt_next``: the step turned the state non-physical and is not
    taken), ``dt = min(dt_cfl, t_out − t)``, landing on ``t_out``."""

    n_records = 1

    def __init__(self, step: Callable):
        self.step = step

    def __call__(self, state, t, dt_cfl, t_out, n_max, dt_floor) -> Stretch:
        dt = min(dt_cfl, t_out - t)
        new, dt_next, probes, forces = self.step(state, t, dt)
        if not np.isfinite(dt_next):
            return Stretch(state, t, dt_next, dt, np.zeros(0), np.zeros((0, 0)), np.zeros((0, 0)))
        t_new = t_out if t + dt >= t_out * (1 - LANDING) else t + dt
        return Stretch(new, t_new, dt_next, dt, np.array([t_new]), np.asarray(probes, float)[None],
                       np.asarray(forces, float)[None])
