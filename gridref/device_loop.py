"""Whole stretches of a grid method's steps in one compiled
``jax.lax.while_loop`` on the device: the time step, the step, the
failure test and the probe and side-force records never return to the
host; :func:`partmesh.cases.march.march` drives it."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.cases.march import LANDING, Stretch
from partmesh.compare.schema import load_result_modules


class DeviceLoop:
    """``loop(state, t, dt_cfl, t_out, n_max, dt_floor) -> Stretch``: up to
    ``n_max`` (≤ ``n_records``) steps of ``step`` in one compiled
    ``jax.lax.while_loop``, each ``dt = min(dt_cfl, t_out − t)`` (the last
    lands on ``t_out``), stopping at ``t_out``, after ``n_max`` steps, at a
    step that turns the state non-physical or at a CFL step below
    ``dt_floor``. A non-physical step is not taken: the loop keeps no copy
    of the last good state (that would cost a pass over the state every
    step), so the steps before it are made again from the stretch's start,
    which the host still holds.

    ``step(state, t, dt) -> (state, dt_next, probes, side_forces)`` is a
    pure function of arrays; ``dt_next`` NaN says the new state is not
    physical. The probes and forces of every step are kept on the device
    and returned with the stretch."""

    def __init__(self, step: Callable, n_probes: int, n_forces: int, n_records: int, per_step: int = 1,
                 halts: bool = False, enter: Callable | None = None, leave: Callable | None = None):
        self.step, self.n_records = step, int(n_records)
        self.enter, self.leave = enter or _same, leave or _same
        self.n_probes, self.n_forces = n_probes, n_forces
        self.per_step, self.halts = int(per_step), halts
        self._compiled, self._shapes = None, None

    def _loop(self, state, t, dt_cfl, t_out, n_max, dt_floor):
        step, n_records, R = self.step, self.n_records, self.per_step
        if R == 1:
            records = (jnp.zeros(n_records, t.dtype), jnp.zeros((n_records, self.n_probes), t.dtype),
                       jnp.zeros((n_records, self.n_forces), t.dtype))
        else:
            records = (jnp.zeros((n_records, R), t.dtype), jnp.zeros((n_records, R, self.n_probes), t.dtype),
                       jnp.zeros((n_records, R, self.n_forces), t.dtype))
        landing = t_out * (1.0 - LANDING)

        def going(carry):
            _, t, dt_cfl, n, _, _, halted = carry
            return (t < landing) & (n < n_max) & jnp.isfinite(dt_cfl) & (dt_cfl >= dt_floor) & ~halted

        def one_step(carry):
            state, t, dt_cfl, n, _, (times, probes, forces), _ = carry
            dt = jnp.minimum(dt_cfl, t_out - t)
            state, dt_next, p, f, *halted = step(state, t, dt)
            halted = halted[0] if self.halts else jnp.zeros((), bool)
            t_new = jnp.where(t + dt >= landing, t_out, t + dt)
            if R > 1:  # the records' times: the ends of the step's R equal parts, the last where the step lands
                t_new = jnp.concatenate([t + dt * (jnp.arange(1, R) / R), t_new[None]])
            records = (times.at[n].set(t_new), probes.at[n].set(p), forces.at[n].set(f))
            t_new = t_new if R == 1 else t_new[-1]
            return (state, jnp.where(halted, t, t_new), dt_next, n + jnp.where(halted, 0, 1), dt, records, halted)

        zero = jnp.zeros((), t.dtype)
        state, *rest = jax.lax.while_loop(going, one_step, (self.enter(state), t, dt_cfl, jnp.zeros((), jnp.int32),
                                                            zero, records, jnp.zeros((), bool)))
        return self.leave(state), *rest

    def compile(self, state) -> None:
        """Compile the loop for the shapes of ``state`` (float64 times), and
        run it once without a step: a first execution's own costs are not
        the run's. Nothing to do where it is compiled for these shapes.
        XLA compiles in a thread of its own (it lets go of the interpreter
        while it does), and this one meanwhile loads the modules the run's
        result needs (:func:`~partmesh.compare.schema.load_result_modules`):
        a first run in a process waits for the longer of the two, not their sum."""
        shapes = jax.tree_util.tree_map(lambda a: (jnp.shape(a), jnp.result_type(a)), state)
        if self._compiled is not None and shapes == self._shapes:
            return
        f = jnp.zeros((), jnp.float64)
        lowered = jax.jit(self._loop).lower(state, f, f, f, jnp.zeros((), jnp.int32), f)
        with ThreadPoolExecutor(1) as pool:
            compiled = pool.submit(lowered.compile)
            load_result_modules()
            self._compiled = compiled.result()
        self._shapes = shapes
        jax.block_until_ready(self._compiled(state, f, f, f, jnp.zeros((), jnp.int32), f))

    def __call__(self, state, t, dt_cfl, t_out, n_max, dt_floor) -> Stretch:
        if self._compiled is None:
            self.compile(state)
        f = lambda x: jnp.asarray(x, jnp.float64)  # noqa: E731
        start = (state, f(t), f(dt_cfl), f(t_out))
        reached, t1, dt_next, n, dt_tried, records, _ = self._compiled(
            *start, jnp.asarray(min(n_max, self.n_records), jnp.int32), f(dt_floor))
        n, dt_next, dt_tried = int(n), float(dt_next), float(dt_tried)
        if not np.isfinite(dt_next):
            # the last step turned the state non-physical: the steps before it, made again from the
            # stretch's start (the same steps, the same state), give the last good state
            n -= 1
            reached, t1, *_ = self._compiled(*start, jnp.asarray(n, jnp.int32), f(dt_floor))
        # (sliced here: a device slice compiles per length)
        times, probes, forces = (np.asarray(a)[:n].reshape((n * self.per_step, *a.shape[2:]) if self.per_step > 1
                                                           else (n, *a.shape[1:])) for a in records)
        return Stretch(reached, float(t1), dt_next, dt_tried, times, probes, forces, steps=n)


def _same(state):
    return state


def device_loop(step: Callable, n_probes: int, n_forces: int, n_records: int = 1024, per_step: int = 1,
                halts: bool = False, enter: Callable | None = None, leave: Callable | None = None) -> DeviceLoop:
    """The compiled stretch loop of ``step``, whose probes and side forces
    are ``n_probes`` and ``n_forces`` numbers, ``per_step`` records of them a
    step (:class:`DeviceLoop`); ``halts``: ``step`` returns a fifth value,
    True where it did not step (the loop stops there, its time unchanged);
    ``enter(state)`` and ``leave(state)``, where given, turn the stretch's
    state into the one ``step`` takes and back, once a stretch (in the
    compiled loop)."""
    return DeviceLoop(step, n_probes, n_forces, n_records, per_step, halts, enter, leave)


