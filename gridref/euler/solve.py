"""The finite-volume Euler reference (method ``fv``): run a scene, return a
schema Dataset on the scene's output grid."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.cases.checkpoint import checkpoint_for
from partmesh.cases.compiling import GRID_SIZE, compiling
from partmesh.cases.history import History, Output, RunRecord
from partmesh.cases.march import Start, Stepping, march
from partmesh.cases.scene import Inflow
from partmesh.compare.regrid import to_output_grid
from partmesh.gridref.euler.method import FVSettings
from partmesh.gridref.euler.refined import solve_refined
from partmesh.gridref.euler.setup import (failure_sentence, gas_of, immersed_for, inflow_states, initial_state,
                                          lighting_for, named_fields, scheme_for)
from partmesh.gridref.euler.state import primitive
from partmesh.gridref.euler.step import FLOOR, Stepper
from partmesh.gridref.grid import bilinear_stencil, cell_centres, solver_grid
from partmesh.gridref.jax_setup import configure_jax
from partmesh.gridref.revolution import GEOMETRIES, revolved
from partmesh.gridref.sharding import sharded


def solve(scene, settings: FVSettings):
    """Run ``scene`` with the unsplit MUSCL–Hancock finite-volume scheme
    and checked ``settings`` (:class:`~partmesh.gridref.euler.method.FVSettings`).

    Returns a schema Dataset; raises :class:`~partmesh.cases.errors.SolverFailed`
    (with the partial result) if the state turns non-physical or the run is
    interrupted. The state is saved to ``settings.checkpoint`` every
    ``checkpoint_every`` seconds and on SIGINT or SIGTERM; ``resume``
    continues from it (:mod:`partmesh.cases.checkpoint`). With
    ``settings.levels`` > 1 the run is refined adaptively
    (:mod:`partmesh.gridref.euler.refined`).
    """
    if settings.levels > 1:
        return solve_refined(scene, settings)
    configure_jax()
    dx, gas, cfl = settings.dx, gas_of(scene), settings.cfl
    grid = solver_grid(scene.domain, dx)
    ib = immersed_for(scene, grid)
    U = sharded(initial_state(scene, grid, None if ib is None else ib.fluid))
    scheme = scheme_for(scene, grid, cfl, settings.limiter, settings.riemann)
    probe_idx, probe_w = bilinear_stencil(grid, [pr.at(scene.dim) for pr in scene.probes] or [(0.0,) * scene.dim])
    probe_pressure = _probe_sampler(probe_idx, probe_w, gas)
    stepper = _stepper_for(scene, scheme, U, ib, probe_pressure, (probe_idx.tobytes(), probe_w.tobytes()),
                           len(probe_w), lighting_for(scene, grid, U))
    with compiling("fv", settings.progress, GRID_SIZE) as compiled:
        stepper.compile(U)
    run = _Run(scene, grid, ib, settings.record(), compile_seconds=compiled.seconds,
               history=History(np.asarray(probe_pressure(tuple(np.asarray(u) for u in U))), 2 * scene.dim,
                               scene.t_start),
               devices=len(U[0].sharding.device_set))
    t, state = scene.t_start, stepper.start(U)
    dt_cfl = float(stepper.initial_dt(U))
    ckpt = checkpoint_for(scene, settings)
    saved = ckpt.saved_state(run)
    if saved is not None:
        (U_saved, floors), t, dt_cfl = saved["state"], saved["t"], saved["dt_cfl"]
        state = (sharded(tuple(jnp.asarray(u) for u in U_saved)), jnp.asarray(floors))

    def diagnose(state, t, step, dt, failed):
        U = state[0]
        if failed:  # the state the failed step of dt made
            (U, _), _, _, _ = stepper.one_step(state, t, dt)
            t = t + dt
        return failure_sentence(U, gas, grid, t, step, dt, None if ib is None else ib.fluid)

    def saved_state(state, t, dt_cfl):
        return {"state": jax.tree_util.tree_map(np.asarray, state), "t": t, "dt_cfl": dt_cfl}

    return march(run, Start(state, t, dt_cfl), Stepping(stepper.stretch, saved_state, diagnose), ckpt, settings)


def _probe_sampler(probe_idx, probe_w, gas):
    """The pressure at the probes: bilinear in the cells of ``probe_idx``."""
    def probe_pressure(U):
        p = primitive(tuple(a.ravel()[probe_idx] for a in U), gas)[-1]
        return (p * probe_w).sum(axis=-1)
    return probe_pressure


#: the steppers of this process's runs without bodies or inflow, by what their compiled program depends on
_STEPPERS: dict = {}
#: how many of them are kept (the oldest is dropped)
_KEPT = 8


def _stepper_for(scene, scheme, U, immersed, probes, stencil, n_probes, lighting=None) -> Stepper:
    """The :class:`~partmesh.gridref.euler.step.Stepper` of a run, sampling
    its ``probes`` (``stencil``: the bytes of their cells and weights).
    Without bodies or inflow sides its program depends only on the scheme,
    the grid's shape and the probes' stencil: a run of the same scheme, grid
    and probes again in this process takes the stepper of the one before,
    whose step is traced and compiled already (a new one costs its tracing,
    about 0.8 s for ``sod``, whatever the persistent compilation cache
    holds). A kept stepper holds neither the scene nor its state. A charge's
    ``lighting`` times (:func:`~partmesh.gridref.euler.setup.lighting_for`)
    drive its programmed burn."""
    inflow = any(isinstance(scene.boundaries[side], Inflow) for side in scene.sides)
    if immersed is not None or inflow or scene.detonation is not None:
        return Stepper(scheme, immersed=immersed, solid_state=U, probe_sampler=probes, n_probes=n_probes,
                       inflow=lambda t: inflow_states(scene, t), lighting=lighting)
    key = (scheme, U[0].shape, stencil)
    if key not in _STEPPERS:
        if len(_STEPPERS) >= _KEPT:
            del _STEPPERS[next(iter(_STEPPERS))]
        _STEPPERS[key] = Stepper(scheme, probe_sampler=probes, n_probes=n_probes)
    return _STEPPERS[key]


class _Run(RunRecord):
    """The record of one fv run; frames are kept on the solver grid and
    regridded onto the output grid when the result is assembled."""

    def __init__(self, scene, grid, immersed, settings, compile_seconds, history, devices=1):
        super().__init__(scene, "fv", settings, compile_seconds, history)
        self.grid = grid
        #: what the state conversions take: γ, or the mixture of a charge's products and air
        self.gas = gas_of(scene)
        #: the devices the grid is split across (:mod:`partmesh.gridref.sharding`)
        self.devices = devices
        #: cells the vacuum floors changed, and the mass and energy they added, up to the latest frame
        self.floors = np.zeros(3)
        #: the open volume fraction of every cell (1 without obstacles) and the cells whose centre is in a body
        self.volume, self.solid = (1.0, None) if immersed is None else (immersed.volume, immersed.solid)

    def fields(self, state):
        U, floors = state
        self.floors = np.asarray(floors)
        return named_fields(primitive(tuple(np.asarray(u) for u in U), self.gas), self.gas, self.scene.fields,
                            self.solid)

    def totals(self, state) -> dict:
        """Mass and energy in the gas (the open part of every cell; of
        revolution, the whole revolved body)."""
        U, _ = state
        cell = float(np.prod(self.grid.step))
        weight = self.volume * revolved(U[0].shape, self.grid.step[0], GEOMETRIES[self.scene.geometry])
        return {name: float(np.sum(weight * np.asarray(U[i]))) * cell for name, i in (("mass", 0), ("energy", -1))}

    def output(self) -> Output:
        scene, out, s = self.scene, self.scene.output, self.settings
        src = cell_centres(self.grid)
        pairs = [c for d in range(scene.dim) for c in (src[d], out.centres(d))]
        fields, how = {}, "identity"
        periodic = scene.periodic
        solid_out = None if self.solid is None else to_output_grid(self.solid.astype(float), *pairs,
                                                                   periodic=periodic)[0] > 0.5
        for name in scene.fields:
            fields[name], how = to_output_grid(self.stacked(name), *pairs, periodic=periodic)
            if solid_out is not None:
                fields[name][:, solid_out] = np.nan
        walls = ", conservative cut-cell immersed boundary (flux redistribution, small cells merged)"
        scheme = (f"unsplit MUSCL-Hancock, {s['limiter']} limiter on primitive variables, {s['riemann'].upper()} flux"
                  f"{walls if self.solid is not None else ''}, a-posteriori positivity fallback to first order, "
                  f"vacuum floors ({FLOOR:g} of the largest density and pressure) where a near-vacuum still "
                  "turns negative")
        cells, mass, energy = self.floors
        attrs = {"regrid": how, "vacuum_floors": int(cells), "vacuum_floor_mass": float(mass),
                 "vacuum_floor_energy": float(energy), "devices": self.devices}
        return Output(fields, solid_out, scheme, int(np.prod(self.grid.shape)), attrs)
