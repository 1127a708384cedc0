"""Input validation: one clear sentence naming the parameter and the allowed
range, raised as :class:`InputError` before any solver starts (SPEC §9)."""

from __future__ import annotations

import math

import numpy as np

from cases.errors import InputError


def positive(name: str, value) -> float:
    """``value`` as a float, which must be finite and > 0."""
    value = number(name, value)
    if not value > 0:
        raise InputError(f"{name} must be positive, got {value:g}.")
    return value


def number(name: str, value) -> float:
    """``value`` as a finite float."""
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}.") from None
    if not math.isfinite(value):
        raise InputError(f"{name} must be finite, got {value}.")
    return value


def in_range(name: str, value, lo: float, hi: float, *, lo_open=False, hi_open=False) -> float:
    """``value`` as a float within [lo, hi] (ends open where asked)."""
    value = number(name, value)
    below = value <= lo if lo_open else value < lo
    above = value >= hi if hi_open else value > hi
    if below or above:
        interval = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
        raise InputError(f"{name} must lie in {interval}, got {value:g}.")
    return value


def choice(name: str, value, options) -> str:
    """``value``, which must be one of ``options``."""
    if value not in options:
        raise InputError(f"{name} must be one of {', '.join(map(str, options))}; got {value!r}.")
    return value


def integer(name: str, value, lo: int, hi: int | None = None) -> int:
    """``value`` as an int ≥ lo (and ≤ hi)."""
    try:
        as_int = int(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an integer, got {value!r}.") from None
    if as_int != value and not (isinstance(value, str) and str(as_int) == value.strip()):
        raise InputError(f"{name} must be an integer, got {value!r}.")
    if as_int < lo or (hi is not None and as_int > hi):
        upper = "" if hi is None else f" and at most {hi}"
        raise InputError(f"{name} must be at least {lo}{upper}, got {as_int}.")
    return as_int


def cfl(value) -> float:
    """A Courant number in (0, 1]."""
    return in_range("cfl", value, 0.0, 1.0, lo_open=True)


def check_scene(scene) -> None:
    """Consistency of a whole scene: domain, boundaries, output times, probes."""
    from cases.scene import BOUNDARY_KINDS, Inflow

    if scene.dim not in (1, 2) or len(scene.domain) != scene.dim:
        raise InputError(f"scene {scene.name}: dim must be 1 or 2 with one (lo, hi) pair per axis.")
    for axis, (lo, hi) in zip("xy", scene.domain):
        if not hi > lo:
            raise InputError(f"scene {scene.name}: domain along {axis} must have hi > lo, got [{lo:g}, {hi:g}].")
    positive("t_end", scene.t_end)
    positive("dx", scene.dx)
    in_range("gamma", scene.gamma, 1.0, 5.0, lo_open=True)
    for side in scene.sides:
        kind = scene.boundaries.get(side)
        if not (kind in BOUNDARY_KINDS or isinstance(kind, Inflow)):
            raise InputError(
                f"scene {scene.name}: boundary {side} must be one of {', '.join(BOUNDARY_KINDS)} or an Inflow, got {kind!r}."
            )
    for lo_side, hi_side in zip(scene.sides[::2], scene.sides[1::2]):
        if (scene.boundaries[lo_side] == "periodic") != (scene.boundaries[hi_side] == "periodic"):
            raise InputError(f"scene {scene.name}: boundaries {lo_side} and {hi_side} must both be periodic or neither.")
    times = np.asarray(scene.output.times, float)
    if times.size == 0 or np.any(np.diff(times) <= 0) or times[0] < 0 or times[-1] > scene.t_end * (1 + 1e-12):
        raise InputError(
            f"scene {scene.name}: output times must increase strictly within [0, t_end={scene.t_end:g}], got {list(times)}."
        )
    for probe in scene.probes:
        inside = all(lo <= c <= hi for c, (lo, hi) in zip((probe.x, probe.y), scene.domain))
        if not inside:
            where = f"({probe.x:g}, {probe.y:g})" if scene.dim == 2 else f"x = {probe.x:g}"
            box = " x ".join(f"[{lo:g}, {hi:g}]" for lo, hi in scene.domain)
            raise InputError(f"probe {probe.name!r} at {where} lies outside the domain {box}.")
        for shape in scene.obstacles:
            if shape.signed_distance(np.array(probe.x), np.array(probe.y)) < 0:
                raise InputError(f"probe {probe.name!r} at ({probe.x:g}, {probe.y:g}) lies inside a solid obstacle.")
    from cases.shapes import overlaps

    for i, a in enumerate(scene.obstacles):
        for j in range(i + 1, len(scene.obstacles)):
            if overlaps(a, scene.obstacles[j]):
                raise InputError(f"scene {scene.name}: obstacles {i} ({a.to_dict()['shape']}) and {j} "
                                 f"({scene.obstacles[j].to_dict()['shape']}) overlap; move them apart.")
