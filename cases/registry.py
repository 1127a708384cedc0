"""The registry of scenes and methods: ``get(name, **overrides)``,
``names()``, ``defaults(name)`` for scenes, ``methods()`` and
``method(name)`` for methods.

A scene builder is a function whose keyword defaults are the scene's
parameters; it validates them and returns a :class:`~partmesh.cases.scene.Scene`.
Builders are found through the entry-point group :data:`SCENE_GROUP` (as
xarray finds its backends): ``sod = "partmesh.cases.verification:sod"`` and
so on, so another package adds a scene by declaring an entry point of its
own, and no scene module is imported until its scene is asked for.
Methods are found the same way through :data:`~partmesh.compare.schema.METHOD_GROUP`
(``fv = "partmesh.gridref.euler.method:METHOD"``), each a
:class:`~partmesh.cases.method.Method`: loading one imports its settings,
not its solver (JAX, numba), which waits until a run's settings and memory
are checked.
"""

from __future__ import annotations

import inspect
from importlib.metadata import entry_points
from typing import Callable

from partmesh.cases.checks import flag
from partmesh.cases.errors import InputError
from partmesh.cases.method import Method
from partmesh.compare.schema import METHOD_GROUP

SCENE_GROUP = "partmesh.scenes"


def _entry_points(group: str) -> dict:
    """name -> entry point of the entry-point ``group``."""
    return {ep.name: ep for ep in entry_points(group=group)}


def _parameters(build: Callable) -> dict:
    """The keyword defaults of a scene builder: the scene's parameters."""
    return {k: p.default for k, p in inspect.signature(build).parameters.items()}


def names() -> list[str]:
    """Names of all registered scenes."""
    return sorted(_entry_points(SCENE_GROUP))


def builder(name: str) -> Callable:
    """The builder function of scene ``name``."""
    found = _entry_points(SCENE_GROUP)
    if name not in found:
        raise InputError(f"unknown case {name!r}; known cases: {', '.join(sorted(found))}.")
    return found[name].load()


def defaults(name: str) -> dict:
    """The parameters of scene ``name`` with their default values."""
    return _parameters(builder(name))


def describe(name: str) -> str:
    """First line of the scene's docstring."""
    return (inspect.getdoc(builder(name)) or "").splitlines()[0]


def _coerce(name: str, key: str, value, default):
    """Values from the command line arrive as strings: convert them to the
    type of the default (numbers stay numbers, ``none`` means None)."""
    if not isinstance(value, str) or isinstance(default, str):
        return value
    if value.lower() == "none":
        return None
    if isinstance(default, bool):
        return flag(f"{name}: parameter {key}", value)
    for kind in ((int, float) if isinstance(default, int) else (float,)):
        try:
            return kind(value)
        except ValueError:
            continue
    if default is None:
        return value
    raise InputError(f"{name}: parameter {key} must be a number, got {value!r}.")


def get(name: str, **overrides):
    """The scene ``name`` with ``overrides`` applied (every one validated)."""
    build = builder(name)
    params = _parameters(build)
    unknown = sorted(set(overrides) - set(params))
    if unknown:
        raise InputError(f"case {name} has no parameter {unknown[0]!r}; parameters: {', '.join(params)}.")
    values = {k: _coerce(name, k, v, params[k]) for k, v in overrides.items()}
    return build(**values)


def methods() -> dict:
    """Registered methods: name -> entry point."""
    return _entry_points(METHOD_GROUP)


def method(name: str) -> Method:
    """The :class:`~partmesh.cases.method.Method` registered as ``name``."""
    available = methods()
    if name not in available:
        raise InputError(f"unknown method {name!r}; available methods: {', '.join(sorted(available)) or 'none'}.")
    return available[name].load()
