"""The finite-volume Euler reference (method ``fv``): run a scene, return a
schema Dataset on the scene's output grid."""

from __future__ import annotations

import time as _time

import jax.numpy as jnp
import numpy as np
from tqdm.auto import tqdm

from cases.checks import cfl as check_cfl
from cases.checks import choice, positive
from cases.errors import InputError, SolverFailed
from cases.scene import Inflow
from compare.regrid import to_output_grid
from compare.schema import result
from gridref.euler.immersed import immersed_boundary
from gridref.euler.reconstruct import LIMITERS
from gridref.euler.riemann import RIEMANN_SOLVERS
from gridref.euler.state import conservative, primitive
from gridref.euler.step import Scheme, Stepper
from gridref.grid import bilinear_stencil, cell_centres, mesh, solver_grid

#: smallest time step, relative to t_end, before a run is declared stalled
DT_FLOOR = 1e-12


def _primitive_state(scene, rho, u, v, p):
    return (rho, u, p) if scene.dim == 1 else (rho, u, v, p)


def _inflow_states(scene, t):
    """Primitive inflow state of every side at time ``t`` (zeros elsewhere)."""
    rows = []
    for side in scene.sides:
        bc = scene.boundaries[side]
        rows.append(_primitive_state(scene, *bc.state(t)) if isinstance(bc, Inflow) else (0.0,) * (scene.dim + 2))
    return np.asarray(rows, float)


def _fields(W, gamma, names, solid):
    W = [np.asarray(a) for a in W]
    rho, p = W[0], W[-1]
    values = {"rho": rho, "u": W[1], "p": p, "e": p / ((gamma - 1.0) * rho)}
    if len(W) == 4:
        values["v"] = W[2]
    out = {}
    for name in names:
        f = np.array(values[name])
        if solid is not None:
            f[solid] = np.nan
        out[name] = f
    return out


def solve(scene, dx=None, cfl=0.8, limiter="mc", riemann="hllc", t_end=None, progress=True, **unknown):
    """Run ``scene`` with the unsplit MUSCL–Hancock finite-volume scheme.

    ``dx`` is the cell size [m] (default: the scene's), ``cfl`` the Courant
    number in (0, 1], ``limiter`` one of ``LIMITERS``, ``riemann`` one of
    ``RIEMANN_SOLVERS``. Returns a schema Dataset; raises
    :class:`~cases.errors.SolverFailed` (with the partial result) if the state
    turns non-physical.
    """
    if unknown:
        raise InputError(f"method fv has no setting {sorted(unknown)[0]!r}; settings: dx, cfl, limiter, riemann.")
    dx = positive("dx", scene.dx if dx is None else dx)
    cfl = check_cfl(cfl)
    choice("limiter", limiter, tuple(LIMITERS))
    choice("riemann", riemann, tuple(RIEMANN_SOLVERS))
    t_end = scene.t_end if t_end is None else positive("t_end", t_end)
    grid = solver_grid(scene.domain, dx)
    gamma = scene.gamma
    X, Y = mesh(grid)
    rho, u, v, p = (np.broadcast_to(np.asarray(a, float), X.shape) for a in scene.initial(X, Y, dx))
    U = conservative(tuple(jnp.asarray(a) for a in _primitive_state(scene, rho, u, v, p)), gamma)

    ib = None
    if scene.obstacles:
        if scene.dim != 2:
            raise InputError(f"scene {scene.name}: obstacles need dim = 2.")
        ib = immersed_boundary(grid, scene.obstacles)
        too_thin = [s for s in scene.obstacles if min(np.ptp(np.array(s.bounds()).reshape(2, 2), axis=0)) < 4 * dx]
        if too_thin:
            raise InputError(
                f"dx = {dx:g} m is too coarse for an obstacle of extent "
                f"{min(np.ptp(np.array(too_thin[0].bounds()).reshape(2, 2), axis=0)):g} m: use at least 4 cells across it."
            )
    kinds = tuple("inflow" if isinstance(scene.boundaries[s], Inflow) else scene.boundaries[s] for s in scene.sides)
    scheme = Scheme(gamma=gamma, dx=tuple(grid.step), kinds=kinds, limiter=limiter, riemann=riemann, cfl=cfl)

    probe_idx, probe_w = bilinear_stencil(grid, [(pr.x, pr.y)[: scene.dim] for pr in scene.probes] or [(0.0,) * scene.dim])

    def probe_pressure(U):
        p = primitive(tuple(a.ravel()[probe_idx] for a in U), gamma)[-1]
        return jnp.sum(p * probe_w, axis=-1)

    U_solid = U
    stepper = Stepper(
        scheme,
        fill_solids=ib.fill if ib is not None else None,
        fluid=jnp.asarray(ib.fluid) if ib is not None else None,
        reset_solids=(lambda V: ib.reset(V, U_solid)) if ib is not None else None,
        probe_sampler=probe_pressure,
    )
    compile_seconds = stepper.compile(U, _inflow_states(scene, 0.0))

    solid = None if ib is None else ~ib.fluid
    out_times = [t for t in scene.output.times if t < t_end * (1 - 1e-12)] + [t_end]
    frames, frame_times = [], []
    t, n_steps = 0.0, 0
    series_t = [0.0]
    series_p = [np.asarray(probe_pressure(U))]
    force_t, force_side = [], []
    impulse_t, impulse_side = [0.0], [np.zeros(2 * scene.dim)]

    def partial_result(status_message):
        W = primitive(U, gamma)
        times = frame_times + ([t] if not frame_times or t > frame_times[-1] else [])
        fr = frames + ([_fields(W, gamma, scene.fields, solid)] if len(times) > len(frames) else [])
        return _assemble(scene, grid, times, fr, solid, series_t, series_p, force_t, force_side, impulse_t,
                         impulse_side, dx, cfl, limiter, riemann, t_end, n_steps, _time.perf_counter() - t_start,
                         compile_seconds, status="failed", failure=status_message)

    t_start = _time.perf_counter()
    dt_cfl = float(stepper.initial_dt(U))
    bar = tqdm(total=t_end, disable=not progress, desc=f"fv {scene.name}", leave=False,
               bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.4g}/{total:.4g} s [{elapsed}<{remaining}] {postfix}")
    try:
        for t_out in out_times:
            while t < t_out * (1 - 1e-14):
                if not np.isfinite(dt_cfl) or dt_cfl < DT_FLOOR * t_end:
                    message = _diagnose(U, gamma, grid, t, n_steps, dt_cfl, solid)
                    raise SolverFailed(message, partial=partial_result(message))
                dt = min(dt_cfl, t_out - t)
                U_new, dt_cfl, forces, probes = stepper(U, dt, _inflow_states(scene, t))
                if not np.isfinite(dt_cfl):
                    # keep the last good state for the diagnosis and the partial result
                    message = _diagnose(U_new, gamma, grid, t + dt, n_steps + 1, dt_cfl, solid)
                    raise SolverFailed(message, partial=partial_result(message))
                U = U_new
                force_t.append(t + 0.5 * dt)
                force_side.append(np.asarray(forces))
                impulse_side.append(impulse_side[-1] + dt * force_side[-1])
                t = t_out if t + dt >= t_out * (1 - 1e-14) else t + dt
                impulse_t.append(t)
                series_t.append(t)
                series_p.append(np.asarray(probes))
                n_steps += 1
                bar.update(dt)
                if n_steps % 50 == 0:
                    bar.set_postfix_str(f"{n_steps} steps")
            frames.append(_fields(primitive(U, gamma), gamma, scene.fields, solid))
            frame_times.append(t)
    except KeyboardInterrupt:
        message = f"fv run of {scene.name} interrupted at t = {t:.6g} s after {n_steps} steps."
        raise SolverFailed(message, partial=partial_result(message)) from None
    finally:
        bar.close()
    wall = _time.perf_counter() - t_start
    return _assemble(scene, grid, frame_times, frames, solid, series_t, series_p, force_t, force_side, impulse_t,
                     impulse_side, dx, cfl, limiter, riemann, t_end, n_steps, wall, compile_seconds)


def _diagnose(U, gamma, grid, t, n_steps, dt, solid):
    """One sentence: when, where and what went wrong."""
    W = [np.asarray(a) for a in primitive(U, gamma)]
    fluid = np.ones(W[0].shape, bool) if solid is None else ~solid
    names = ["density", "pressure"]
    for k, name in zip((0, -1), names):
        bad = fluid & ~(W[k] > 0)
        if np.any(bad):
            where = np.unravel_index(np.flatnonzero(bad)[0], bad.shape)
            coords = [c[i] for c, i in zip(cell_centres(grid), where[::-1])]
            at = ", ".join(f"{a} = {c:.6g} m" for a, c in zip("xy", coords))
            return (f"fv became unstable at t = {t:.6g} s (step {n_steps}): {name} {W[k][where]:.3g} "
                    f"is not positive at {at}.")
    return f"fv time step collapsed to {dt:.3g} s at t = {t:.6g} s (step {n_steps})."


def _assemble(scene, grid, times, frames, solid, series_t, series_p, force_t, force_side, impulse_t, impulse_side,
              dx, cfl, limiter, riemann, t_end, n_steps, wall, compile_seconds, status="ok", failure=None):
    """The schema Dataset of an fv run (fields regridded onto the output grid)."""
    out = scene.output
    src = cell_centres(grid)
    fields, how = {}, "identity"
    for name in scene.fields:
        stack = np.stack([f[name] for f in frames])
        fields[name], how = to_output_grid(stack, src[0], out.x, *( (src[1], out.y) if scene.dim == 2 else ()))
    solid_out = None
    if solid is not None:
        solid_out = to_output_grid(solid.astype(float), src[0], out.x, src[1], out.y)[0] > 0.5
    t_probe = out.probe_times(min(t_end, times[-1]))
    series = {}
    if scene.probes:
        series["p_probe"] = np.stack([np.interp(t_probe, series_t, s) for s in np.stack(series_p).T], axis=1)
    if scene.wall is not None and force_t:
        side = scene.sides.index(scene.wall.side)
        length = scene.wall.height if scene.dim == 1 else (scene.domain[1 - side // 2][1] - scene.domain[1 - side // 2][0])
        scale = scene.wall.height if scene.dim == 1 else 1.0
        base = scene.wall.p0 * (1.0 if scene.dim == 1 else length)
        force = (np.stack(force_side)[:, side] - base) * scale
        series["wall_force"] = np.interp(t_probe, force_t, force)
        impulse = (np.stack(impulse_side)[:, side] - base * np.asarray(impulse_t)) * scale
        series["wall_impulse"] = np.interp(t_probe, impulse_t, impulse)
    attrs = {"regrid": how, "status": status}
    if failure:
        attrs["failure"] = failure
    return result(
        case=scene.name, method="fv",
        scheme=f"unsplit MUSCL-Hancock, {limiter} limiter on primitive variables, {riemann.upper()} flux"
               f"{', ghost-cell immersed boundary' if solid is not None else ''}, positivity fallback to first order",
        x=out.x, y=out.y, times=np.asarray(times), fields=fields, solid=solid_out,
        probes={pr.name: (pr.x, pr.y) for pr in scene.probes} or None,
        t_probe=t_probe if series else None, series=series,
        parameters={"scene": scene.to_dict(), "solver": {"method": "fv", "dx": dx, "cfl": cfl, "limiter": limiter,
                                                         "riemann": riemann, "t_end": t_end}},
        dx=dx, n_elements=int(np.prod(grid.shape)), n_steps=n_steps, wall_seconds=wall,
        compile_seconds=compile_seconds, **attrs,
    )
