"""The time loop the grid solvers share: steps at the CFL time step through
the scene's output times, a frame at each, the probe and side-force history,
progress, checkpoints, and a clean stop with the partial result."""

from __future__ import annotations

import jax
import numpy as np

#: smallest time step, relative to t_end, before a run is declared stalled
DT_FLOOR = 1e-12


def march(run, U, t: float, dt_cfl: float, t_end: float, advance, diagnose, ckpt, bar):
    """Advance the state ``U`` from ``t`` to ``t_end`` and return the run's
    Dataset.

    ``advance(U, t, t_out, dt_cfl) -> (U, t, dt_cfl, probes, side_forces,
    steps)`` makes one or more steps toward the output time ``t_out`` (never
    past it) and returns the state reached, its time, its CFL step (NaN if a
    step turned the state non-physical: then the state and time returned are
    the last good ones), the probe values there, the side forces averaged
    over the steps and how many steps it made; ``diagnose(U, t, step, dt) ->
    str`` says in one sentence when, where and what went wrong after the
    good state ``U`` at ``t``. A non-physical step raises
    :class:`~cases.errors.SolverFailed` carrying the result up to the last
    good state; ``ckpt`` (:mod:`cases.checkpoint`) saves ``U``, ``t`` and
    ``dt_cfl``, and ``bar`` shows the progress.
    """
    out_times = [s for s in run.scene.output.times if s < t_end * (1 - 1e-12)] + [t_end]
    with ckpt.watching_signals():
        try:
            for t_out in out_times[len(run.frame_times):]:  # (one frame per output time)
                while t < t_out * (1 - 1e-14):
                    if not np.isfinite(dt_cfl) or dt_cfl < DT_FLOOR * t_end:
                        raise run.failure(diagnose(U, t, run.n_steps, dt_cfl), t, lambda: run.fields(U))
                    U_new, t_new, dt_cfl, probes, forces, steps = advance(U, t, t_out, dt_cfl)
                    if t_new > t:
                        run.history.record(t, t_new, probes, forces)
                        run.n_steps += steps
                        bar.update(t_new - t)
                    U, t = U_new, t_new
                    if not np.isfinite(dt_cfl):
                        # the last good state is kept for the partial result
                        raise run.failure(diagnose(U, t, run.n_steps + 1, dt_cfl), t, lambda: run.fields(U))
                    bar.set_postfix_str(f"{run.n_steps} steps", refresh=False)
                    ckpt.step_done(run, t, lambda: {"U": jax.tree_util.tree_map(np.asarray, U), "t": t,
                                                    "dt_cfl": dt_cfl}, lambda: run.fields(U))
                run.add_frame(run.fields(U), t)
        finally:
            bar.close()
    return run.dataset()
