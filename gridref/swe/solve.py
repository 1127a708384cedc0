"""The shallow-water model (method ``swe``): run a water scene, return a
schema Dataset on the scene's output grid (SPEC §3.5)."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.cases.checkpoint import checkpoint_for
from partmesh.cases.compiling import GRID_SIZE, compiling
from partmesh.cases.errors import InputError
from partmesh.cases.history import History, Output, RunRecord
from partmesh.cases.march import Start, Stepping, march
from partmesh.compare.regrid import to_output_grid
from partmesh.gridref.device_loop import device_loop
from partmesh.gridref.grid import bilinear_stencil, cell_centres, mesh, solver_grid
from partmesh.gridref.jax_setup import configure_jax
from partmesh.gridref.staging import staged
from partmesh.gridref.swe.method import SWESettings
from partmesh.gridref.swe.step import (
    DRY,
    PRECISIONS,
    Scheme,
    face_fluxes,
    ghosted,
    predicted,
    radii,
    stable_dt,
    updated,
    velocities,
)


class Stepper:
    """The MUSCL–Hancock step of one run, and stretches of it on the device.

    :meth:`step` is the pure step ``U, t, dt -> (U', dt_next, eta at the
    gauges, side forces (none))``: ghost cells, the predicted cells, the
    face fluxes of each direction and the update (:mod:`partmesh.gridref.swe.step`),
    each a stage of its own (:mod:`partmesh.gridref.staging`: fused into one
    program, XLA:CPU computes the new state again for every reduction);
    ``dt_next`` is NaN if the new state is not physical. :attr:`stretch`
    runs it in one compiled loop (:func:`partmesh.gridref.device_loop.device_loop`).
    """

    def __init__(self, scheme: Scheme, z, radius, gauge_index, gauge_weight, dtype):
        def gauges(U):
            return jnp.sum((U[0] + z).ravel()[gauge_index] * gauge_weight, axis=-1)

        def checked(U):
            return stable_dt(U, scheme), gauges(U)

        no_forces = jnp.zeros(2 * scheme.dim)

        def step(U, t, dt):
            gate, dt = jnp.isfinite(dt), jnp.asarray(dt).astype(dtype)
            Wg = staged(lambda U: ghosted(U, z, scheme), gate)(U)
            P = staged(lambda Wg, dt: predicted(Wg, dt, scheme, radius), gate)(Wg, dt)
            fluxes = [staged(lambda P, d=d: face_fluxes(P, d, scheme), gate)(P) for d in range(scheme.dim)]
            U_new = staged(lambda U, P, F, dt: updated(U, P, F, dt, scheme, radius), gate)(U, P, fluxes, dt)
            dt_next, eta = staged(checked, gate)(U_new)
            return U_new, dt_next.astype(t.dtype), eta, no_forces

        self.step = step
        #: one step, compiled when first called
        self.one_step = jax.jit(step)
        self.stretch = device_loop(step, len(gauge_weight), 2 * scheme.dim)
        self.initial_dt = jax.jit(lambda U: checked(U)[0])

    def compile(self, U) -> None:
        """Compile the stretch for these shapes (and the first CFL step)."""
        jax.block_until_ready(self.initial_dt(U))
        self.stretch.compile(U)


def solve(scene, settings: SWESettings):
    """Run the water ``scene`` with the shallow-water model and checked
    ``settings`` (:class:`~partmesh.gridref.swe.method.SWESettings`): MUSCL–Hancock
    (the limiter on depth, surface and velocity), hydrostatic
    reconstruction at the faces, HLLC fluxes.

    Returns a schema Dataset with ``eta`` (NaN over dry cells), the
    depth-averaged velocity and ``h``; raises
    :class:`~partmesh.cases.errors.SolverFailed` with the partial result if a depth
    turns negative or the run is interrupted. Checkpoints as in the other
    methods (:mod:`partmesh.cases.checkpoint`).
    """
    configure_jax()
    dx = settings.dx
    grid = solver_grid(scene.domain, dx)
    X, Y = mesh(grid)
    z = np.broadcast_to(np.asarray(scene.bed(X, Y), float), X.shape)
    eta0, u0, v0 = (np.broadcast_to(np.asarray(a, float), X.shape) for a in scene.initial(X, Y))
    h0 = np.maximum(eta0 - z, 0.0)
    for name, a in (("bed", z), ("initial surface", eta0), ("initial velocity", u0)):
        if not np.all(np.isfinite(a)):
            raise InputError(f"scene {scene.name}: the {name} must be finite everywhere.")
    dtype = PRECISIONS[settings.precision]
    U = tuple(jnp.asarray(np.asarray(a, dtype)) for a in (h0, h0 * u0, h0 * v0)[: 1 + scene.dim])
    scheme = Scheme(g=scene.g, dx=tuple(grid.step), kinds=tuple(scene.boundaries[s] for s in scene.sides),
                    radial=scene.geometry == "radial", limiter=settings.limiter, cfl=settings.cfl)
    radius = radii(cell_centres(grid)[0], grid.step[0], dtype) if scheme.radial else None
    gauges = [pr.at(scene.dim) for pr in scene.probes] or [(X.flat[0], 0.0)[: scene.dim]]
    gauge_index, gauge_weight = bilinear_stencil(grid, gauges)
    stepper = Stepper(scheme, jnp.asarray(np.asarray(z, dtype)), radius, jnp.asarray(gauge_index),
                      jnp.asarray(gauge_weight), dtype)
    with compiling("swe", settings.progress, GRID_SIZE) as compiled:
        stepper.compile(U)
    run = _Run(scene, grid, z, settings.record(), compiled.seconds,
               History(np.sum((h0 + z).ravel()[gauge_index] * gauge_weight, axis=-1), 2 * scene.dim))
    t, dt_cfl = 0.0, float(stepper.initial_dt(U))
    ckpt = checkpoint_for(scene, settings)
    saved = ckpt.saved_state(run)
    if saved is not None:
        U, t, dt_cfl = tuple(jnp.asarray(a, dtype) for a in saved["U"]), saved["t"], saved["dt_cfl"]

    def diagnose(U, t, step, dt, failed):
        if failed:  # the state the failed step of dt made
            U, t = stepper.one_step(U, t, dt)[0], t + dt
        return run.diagnosis(U, t, step, dt)

    def saved_state(U, t, dt_cfl):
        return {"U": [np.asarray(a) for a in U], "t": t, "dt_cfl": dt_cfl}

    return march(run, Start(U, t, dt_cfl), Stepping(stepper.stretch, saved_state, diagnose), ckpt, settings)


class _Run(RunRecord):
    """The record of one swe run; frames are kept on the solver grid and
    regridded onto the output grid when the result is assembled."""

    def __init__(self, scene, grid, z, settings, compile_seconds, history):
        super().__init__(scene, "swe", settings, compile_seconds, history)
        self.grid, self.z = grid, z

    def fields(self, U) -> dict:
        U = tuple(np.asarray(u) for u in U)
        h = U[0]
        vel = velocities(U, np)
        eta = np.where(h > DRY, h + self.z, np.nan)
        values = {"eta": eta, "h": h, "u": vel[0]}
        if len(vel) == 2:
            values["v"] = vel[1]
        return {name: values[name] for name in self.scene.fields}

    def diagnosis(self, U, t, step, dt) -> str:
        """One sentence: when, where and what went wrong in the state ``U`` at ``t``."""
        h = np.asarray(U[0])
        bad = ~(h >= 0.0) | ~np.all([np.isfinite(np.asarray(a)) for a in U], axis=0)
        if np.any(bad):
            where = np.unravel_index(np.flatnonzero(bad)[0], bad.shape)
            at = ", ".join(f"{a} = {c[i]:.6g} m" for a, c, i in zip("xy", cell_centres(self.grid), where[::-1]))
            return (f"swe became unstable at t = {t:.6g} s (step {step}): depth {h[where]:.3g} m "
                    f"at {at}; lower cfl (now {self.settings['cfl']:g}; the depth is kept non-negative up to 0.25).")
        return f"swe time step collapsed to {dt:.3g} s at t = {t:.6g} s (step {step})."

    def output(self) -> Output:
        scene, out, s = self.scene, self.scene.output, self.settings
        src = cell_centres(self.grid)
        pairs = (src[0], out.x) if scene.dim == 1 else (src[0], out.x, src[1], out.y)
        fields, how = {}, "identity"
        for name in scene.fields:
            fields[name], how = to_output_grid(self.stacked(name), *pairs)
        geometry = "1D-radial" if scene.geometry == "radial" else f"{scene.dim}D"
        scheme = (f"{geometry} shallow water: MUSCL-Hancock ({s['limiter']} limiter on h, eta, velocity), "
                  f"hydrostatic reconstruction (Audusse et al. 2004), HLLC flux, {s['precision']}")
        long_names = {"u": "depth-averaged velocity x", "v": "depth-averaged velocity y"}
        return Output(fields, None, scheme, int(np.prod(self.grid.shape)), {"regrid": how, "long_names": long_names})
