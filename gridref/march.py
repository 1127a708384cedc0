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

    ``advance(U, dt, t) -> (U, dt_cfl, probes, side_forces)`` makes one step
    and returns the CFL step of the new state (NaN if it is not physical);
    ``diagnose(U, t, step, dt) -> str`` says in one sentence when, where and
    what went wrong. A non-physical step raises
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
                    dt = min(dt_cfl, t_out - t)
                    U_new, dt_cfl, probes, forces = advance(U, dt, t)
                    if not np.isfinite(dt_cfl):
                        # the last good state is kept for the partial result
                        raise run.failure(diagnose(U_new, t + dt, run.n_steps + 1, dt_cfl), t, lambda: run.fields(U))
                    U = U_new
                    t_new = t_out if t + dt >= t_out * (1 - 1e-14) else t + dt
                    run.history.record(t, t_new, probes, forces)
                    run.n_steps += 1
                    bar.update(t_new - t)
                    t = t_new
                    if run.n_steps % 50 == 0:
                        bar.set_postfix_str(f"{run.n_steps} steps")
                    ckpt.step_done(run, t, lambda: {"U": jax.tree_util.tree_map(np.asarray, U), "t": t,
                                                    "dt_cfl": dt_cfl}, lambda: run.fields(U))
                run.add_frame(run.fields(U), t)
        finally:
            bar.close()
    return run.dataset()
