"""Input validation: one clear sentence naming the parameter and the allowed
range, raised as :class:`InputError` before any solver starts (SPEC §9)."""

from __future__ import annotations

import numpy as np

from partmesh.cases.errors import InputError
from partmesh.cases.parts import Inflow
from partmesh.cases.shape_queries import overlaps
from partmesh.compare.checks import (
    choice,
    flag,
    in_range,
    integer,
    non_negative,
    number,
    positive,
)

__all__ = ["GAS_GEOMETRIES", "check_geometry", "check_scene", "choice", "flag", "in_range", "integer",
           "non_negative", "number", "positive"]


def check_scene(scene) -> None:
    """Consistency of a whole scene: domain, boundaries, output times, probes."""
    if scene.dim not in (1, 2, 3) or len(scene.domain) != scene.dim:
        raise InputError(f"scene {scene.name}: dim must be 1, 2 or 3 with one (lo, hi) pair per axis.")
    if scene.dim == 3 and (scene.obstacles or scene.wall is not None or scene.medium != "gas"
                           or any(isinstance(kind, Inflow) for kind in scene.boundaries.values())):
        raise InputError(f"scene {scene.name}: a 3D scene is a gas in a box for now, without obstacles, a "
                         "target wall or an inflow side.")
    for axis, (lo, hi) in zip("xyz", scene.domain):
        if not hi > lo:
            raise InputError(f"scene {scene.name}: domain along {axis} must have hi > lo, got [{lo:g}, {hi:g}].")
    positive("t_end", scene.t_end)
    positive("dx", scene.dx)
    gas = scene.medium == "gas"  # (an Inflow imposes a gas state)
    for side in scene.sides:
        kind = scene.boundaries.get(side)
        if not (kind in scene.boundary_kinds or (gas and isinstance(kind, Inflow))):
            allowed = ", ".join(scene.boundary_kinds) + (" or an Inflow" if gas else "")
            raise InputError(f"scene {scene.name}: boundary {side} must be one of {allowed}, got {kind!r}.")
    for lo_side, hi_side in zip(scene.sides[::2], scene.sides[1::2]):
        if (scene.boundaries[lo_side] == "periodic") != (scene.boundaries[hi_side] == "periodic"):
            raise InputError(f"scene {scene.name}: boundaries {lo_side} and {hi_side} must both be periodic or neither.")
    times = np.asarray(scene.output.times, float)
    t0 = non_negative("t_start", scene.t_start)
    if not scene.t_end > t0:
        raise InputError(f"scene {scene.name}: t_end must be later than t_start = {t0:g} s, got {scene.t_end:g} s.")
    if times.size == 0 or np.any(np.diff(times) <= 0) or times[0] < t0 or times[-1] > scene.t_end * (1 + 1e-12):
        raise InputError(f"scene {scene.name}: output times must increase strictly within [t_start={t0:g}, "
                         f"t_end={scene.t_end:g}], got {list(times)}.")
    for probe in scene.probes:
        if scene.geometry != "planar" and probe.x < 0.0:
            raise InputError(f"probe {probe.name!r} of scene {scene.name} lies at r = {probe.x:g} m; in an "
                             f"{scene.geometry} scene the radius r (x) must be >= 0.")
        inside = all(lo <= c <= hi for c, (lo, hi) in zip((probe.x, probe.y, probe.z), scene.domain))
        if not inside:
            where = (f"x = {probe.x:g}" if scene.dim == 1 else
                     "(" + ", ".join(f"{c:g}" for c in (probe.x, probe.y, probe.z)[: scene.dim]) + ")")
            box = " x ".join(f"[{lo:g}, {hi:g}]" for lo, hi in scene.domain)
            raise InputError(f"probe {probe.name!r} at {where} lies outside the domain {box}.")
        for shape in scene.obstacles:
            if shape.signed_distance(np.array(probe.x), np.array(probe.y)) < 0:
                raise InputError(f"probe {probe.name!r} at ({probe.x:g}, {probe.y:g}) lies inside a solid obstacle.")
    for i, a in enumerate(scene.obstacles):
        for j in range(i + 1, len(scene.obstacles)):
            if overlaps(a, scene.obstacles[j]):
                raise InputError(f"scene {scene.name}: obstacles {i} ({a.to_dict()['shape']}) and {j} "
                                 f"({scene.obstacles[j].to_dict()['shape']}) overlap; move them apart.")


#: the geometries of a gas scene (:class:`~partmesh.cases.scene.Scene`)
GAS_GEOMETRIES = ("planar", "axisymmetric", "spherical")


def check_geometry(scene) -> None:
    """A geometry of revolution starts at its axis (or centre): the domain
    along x (r) begins at 0 with a reflecting ``x_lo``, a sphere is 1D, no
    obstacle lies at r < 0 (a probe there is refused by :func:`check_scene`)
    and a 1D target wall is planar."""
    choice("geometry", scene.geometry, GAS_GEOMETRIES)
    if scene.geometry == "planar":
        return
    if scene.dim == 3:
        raise InputError(f"scene {scene.name}: a 3D scene is planar (x, y, z), got geometry {scene.geometry!r}.")
    if scene.geometry == "spherical" and scene.dim != 1:
        raise InputError(f"scene {scene.name}: a spherical scene is 1D (x the distance from the centre); "
                         "in 2D a sphere is an axisymmetric scene.")
    lo = scene.domain[0][0]
    if lo != 0.0:
        raise InputError(f"scene {scene.name}: an {scene.geometry} scene begins at its axis, so its domain along x "
                         f"(the radius r) must start at 0, got {lo:g} m.")
    if scene.boundaries.get("x_lo") != "reflect":
        raise InputError(f"scene {scene.name}: the axis of an {scene.geometry} scene (side x_lo, r = 0) is a "
                         f"symmetry boundary and must be 'reflect', got {scene.boundaries.get('x_lo')!r}.")
    if scene.wall is not None and scene.dim == 1:
        raise InputError(f"scene {scene.name}: a target wall needs a planar scene in 1D (its load is per square "
                         f"metre of a plane wall); {scene.name} is {scene.geometry}.")
    for i, shape in enumerate(scene.obstacles):
        xmin = shape.bounds()[0]
        if xmin < 0.0:
            raise InputError(f"scene {scene.name}: obstacle {i} ({shape.to_dict()['shape']}) crosses the axis "
                             f"(it reaches r = {xmin:g} m); in an axisymmetric scene a body is its cross-section "
                             "at r >= 0, a body on the axis the half that touches x = 0.")


def _same_shape(a, b, tol: float) -> bool:
    """True when shapes ``a`` and ``b`` are the same body to ``tol`` [m]."""
    da, db = a.to_dict(), b.to_dict()
    if da.keys() != db.keys() or da["shape"] != db["shape"]:
        return False
    return all(np.allclose(np.asarray(da[k], float), np.asarray(db[k], float), rtol=0.0, atol=tol)
               for k in da if k != "shape")


def check_obstacles(scene, dx: float) -> None:
    """Refuse obstacles a run at spacing ``dx`` cannot represent: one less
    than 4 cells (particle spacings) across; one that reaches an inflow
    side (the inflow buffer carries no solid); one cut by a periodic side
    whose other part, the same shape shifted by one period, is not listed
    (the gas would flow through the missing half)."""
    if scene.obstacles and scene.dim != 2:
        raise InputError(f"scene {scene.name}: obstacles need dim = 2.")
    for i, shape in enumerate(scene.obstacles):
        xmin, ymin, xmax, ymax = shape.bounds()
        extent = min(xmax - xmin, ymax - ymin)
        if extent < 4 * dx:
            raise InputError(f"dx = {dx:g} m is too coarse for an obstacle of extent {extent:g} m: "
                             f"use at least 4 cells across it (dx <= {extent / 4:g} m).")
        for d, side in enumerate(scene.sides):
            kind = scene.boundaries[side]
            if not (kind == "periodic" or isinstance(kind, Inflow)):
                continue
            axis, upper = d // 2, d % 2 == 1
            lo_edge, hi_edge = scene.domain[axis]
            edge = hi_edge if upper else lo_edge
            lo, hi = (xmin, xmax) if axis == 0 else (ymin, ymax)
            if not ((hi > edge) if upper else (lo < edge)):
                continue
            if isinstance(kind, Inflow):
                raise InputError(f"scene {scene.name}: obstacle {i} ({shape.to_dict()['shape']}) reaches the "
                                 f"inflow side {side} ({'xy'[axis]} = {edge:g} m); keep obstacles clear of it.")
            period = (hi_edge - lo_edge) * (-1.0 if upper else 1.0)
            image = shape.translated(period if axis == 0 else 0.0, period if axis == 1 else 0.0)
            if not any(_same_shape(image, other, 1e-9 * abs(period)) for other in scene.obstacles):
                raise InputError(f"scene {scene.name}: obstacle {i} ({shape.to_dict()['shape']}) is cut by the "
                                 f"periodic side {side} ({'xy'[axis]} = {edge:g} m) but its other part, shifted "
                                 f"by {period:g} m, is not an obstacle of the scene; list both parts.")


def check_initial_state(scene, rho, p, x, y=None, z=None, fluid=None) -> None:
    """Refuse an initial state with non-positive (or non-finite) density or
    pressure in the fluid, naming the first offending point."""
    for name, values in (("density", rho), ("pressure", p)):
        bad = ~(np.asarray(values) > 0) | ~np.isfinite(values)
        if fluid is not None:
            bad &= fluid
        if np.any(bad):
            k = np.flatnonzero(bad)[0]
            at = ", ".join(f"{a} = {np.ravel(c)[k]:.6g} m" for a, c in zip("xyz", (x, y, z)) if c is not None)
            raise InputError(f"scene {scene.name}: initial {name} must be positive and finite, "
                             f"got {np.ravel(values)[k]:g} at {at}.")
