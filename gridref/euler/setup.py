"""What a run of a scene on the finite-volume grid starts from: its initial
state, the inflow state of its sides at any time, its scheme; and the
sentence a run that fails ends with."""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.cases.checks import check_initial_state, check_obstacles
from partmesh.cases.errors import InputError
from partmesh.cases.scene import Inflow
from partmesh.gridref.euler.immersed import immersed_boundary
from partmesh.gridref.euler.method import boundary_kinds
from partmesh.gridref.euler.mixture import Mixture, lighting_times
from partmesh.gridref.euler.state import conservative, internal_energy, parts, primitive, scalar_count
from partmesh.gridref.euler.step import Scheme
from partmesh.gridref.grid import cell_centres, mesh
from partmesh.gridref.revolution import GEOMETRIES


def _primitive_state(scene, rho, u, v, p):
    """The scene's primitive state ``(rho, u, v, p)`` in the solver's layout: ``(rho, u, p)`` in 1D."""
    return (rho, u, p) if scene.dim == 1 else (rho, u, v, p)


def inflow_states(scene, t):
    """Primitive inflow state of every side at the traced time ``t`` (zeros
    elsewhere), for the compiled loop; beside a charge, the inflow is air
    (its mixture scalars zero)."""
    rows, scalars = [], (0.0,) * scalar_count(gas_of(scene))
    for side in scene.sides:
        bc = scene.boundaries[side]
        if isinstance(bc, Inflow):
            try:
                state = _primitive_state(scene, *bc.state(t, xp=jnp))
            except jax.errors.JAXTypeError as error:
                raise InputError(f"the inflow state of side {side} of scene {scene.name} cannot be evaluated inside "
                                 "the compiled time loop: write it with the array namespace it is given "
                                 f"(state(t, xp)) ({type(error).__name__}).") from None
            state = (*state[:-1], *scalars, state[-1])
            rows.append(jnp.stack([jnp.asarray(a, dtype=float) for a in state]))
        else:
            rows.append(jnp.zeros(scene.dim + 2 + len(scalars)))
    return jnp.stack(rows)


def initial_state(scene, grid, fluid=None):
    """The scene's initial state on ``grid`` as conservative variables
    (checked: positive density and pressure in the ``fluid`` cells); a 3D
    scene's ``initial(x, y, dx, z)`` gives ``(rho, u, v, w, p)``. A scene's
    charge (:class:`~partmesh.cases.parts.Detonation`) fills its fraction
    α of every cell, unburnt, at the air's velocity and pressure."""
    points = mesh(grid)
    dx = float(grid.step[0])
    W = scene.initial(*points[:2], dx, *points[2:])
    W = tuple(np.broadcast_to(np.asarray(a, float), points[0].shape) for a in W)
    check_initial_state(scene, W[0], W[-1], *points, fluid=fluid)
    W = W if scene.dim == 3 else _primitive_state(scene, *W)
    charge = scene.detonation
    if charge is not None:
        alpha = np.broadcast_to(np.asarray(charge.fraction(*points[:2], dx), float), points[0].shape)
        density = charge.density(*points[:2], dx) if callable(charge.density) else charge.density
        rho_y = alpha * (charge.explosive.rho0 if density is None else np.asarray(density, float))
        W = (rho_y + (1.0 - alpha) * W[0], *W[1:-1], rho_y, rho_y if charge.burnt else np.zeros_like(alpha), alpha,
             W[-1])
    # (in numpy: an ideal gas's conversion is arithmetic alone, which jax would compile for each grid size)
    return tuple(jnp.asarray(u) for u in conservative(tuple(np.asarray(a) for a in W), gas_of(scene)))


def gas_of(scene):
    """What the fv state conversions take for ``scene`` (:mod:`partmesh.gridref.euler.state`): its γ, or, with
    a charge, the :class:`~partmesh.gridref.euler.mixture.Mixture` of its products and air."""
    charge = scene.detonation
    return scene.gamma if charge is None else _mixture(charge.explosive, scene.gamma)


@functools.cache
def _mixture(explosive, gamma: float) -> Mixture:
    """The one :class:`~partmesh.gridref.euler.mixture.Mixture` of ``explosive`` and air of ``gamma`` in this
    process: its CJ speed solved, and its isentrope tabulated, once."""
    return Mixture(explosive, gamma, explosive.cj_state().D)


def lighting_for(scene, grid, U):
    """The programmed burn's lighting time of every cell of ``grid``
    (:func:`~partmesh.gridref.euler.mixture.lighting_times`): the cells
    that hold explosive in the initial state ``U``; None without a charge
    to burn."""
    charge = scene.detonation
    if charge is None or charge.burnt:
        return None
    points = mesh(grid)
    coordinates = [points[0]] if scene.dim == 1 else list(points)
    return lighting_times(coordinates, np.asarray(U[-2]), charge.initiation, gas_of(scene).burn_speed)


def immersed_for(scene, grid):
    """The immersed boundary of the scene's obstacles on ``grid`` (or None),
    refusing a grid too coarse to resolve them."""
    check_obstacles(scene, float(grid.step[0]))
    if not scene.obstacles:
        return None
    return immersed_boundary(grid, scene.obstacles, scene.periodic, radial=GEOMETRIES[scene.geometry])


def scheme_for(scene, grid, cfl, limiter, riemann) -> Scheme:
    """The MUSCL–Hancock scheme of ``scene`` on ``grid`` (its boundary kinds per side)."""
    return Scheme(gamma=scene.gamma, dx=tuple(grid.step), kinds=boundary_kinds(scene), limiter=limiter, riemann=riemann,
                  cfl=cfl, radial=GEOMETRIES[scene.geometry],
                  mixture=None if scene.detonation is None else gas_of(scene))


def failure_sentence(U, gas, grid, t, n_steps, dt, fluid=None):
    """One sentence: when, where and what went wrong."""
    W = [np.asarray(a) for a in primitive(U, gas)]
    fluid = np.ones(W[0].shape, bool) if fluid is None else fluid
    for k, name in ((0, "density"), (-1, "pressure")):
        bad = fluid & ~(W[k] > 0)
        if np.any(bad):
            where = np.unravel_index(np.flatnonzero(bad)[0], bad.shape)
            coords = [c[i] for c, i in zip(cell_centres(grid), where[::-1])]
            at = ", ".join(f"{a} = {c:.6g} m" for a, c in zip("xyz", coords))
            return (f"fv became unstable at t = {t:.6g} s (step {n_steps}): {name} {W[k][where]:.3g} "
                    f"is not positive at {at}.")
    return f"fv time step collapsed to {dt:.3g} s at t = {t:.6g} s (step {n_steps})."


def named_fields(W, gas, names, solid=None) -> dict:
    """The schema's fields ``names`` (of rho, u, v, w, p, e; Y and alpha, the products' mass
    and volume fractions, of a mixture) from the primitive state ``W`` (of ``gas``: γ or a
    mixture) as numpy arrays, NaN in the ``solid`` cells."""
    rho, vel, scalars, p = parts([np.asarray(a) for a in W], gas)
    e = (p / ((gas - 1.0) * rho) if not scalar_count(gas) else
         np.asarray(internal_energy(rho, scalars, p, gas)) / rho)
    values = {"rho": rho, "p": p, "e": e, **dict(zip("uvw", vel))}
    if scalar_count(gas):
        values["Y"], values["alpha"] = np.clip(scalars[0] / rho, 0.0, 1.0), scalars[2]
    out = {}
    for name in names:
        f = np.array(values[name])
        if solid is not None:
            f[solid] = np.nan
        out[name] = f
    return out
