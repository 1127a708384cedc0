"""The scene registry: ``get(name, **overrides)``, ``names()``, ``defaults(name)``.

A scene builder is a function whose keyword defaults are the scene's
parameters; it validates them and returns a :class:`~cases.scene.Scene`.
Registering it with :func:`scene_builder` makes it available by name.
"""

from __future__ import annotations

import inspect
from typing import Callable

from cases.checks import flag
from cases.errors import InputError

_BUILDERS: dict[str, Callable] = {}


def scene_builder(name: str):
    """Decorator: register ``builder`` as the scene ``name``."""

    def register(builder):
        _BUILDERS[name] = builder
        return builder

    return register


def _load():
    # the scene modules register themselves on import
    from cases import blast, dsmc_study, verification, water  # noqa: F401


def names() -> list[str]:
    """Names of all registered scenes."""
    _load()
    return sorted(_BUILDERS)


def _builder(name: str) -> Callable:
    _load()
    if name not in _BUILDERS:
        raise InputError(f"unknown case {name!r}; known cases: {', '.join(sorted(_BUILDERS))}.")
    return _BUILDERS[name]


def defaults(name: str) -> dict:
    """The parameters of scene ``name`` with their default values."""
    return {k: p.default for k, p in inspect.signature(_builder(name)).parameters.items()}


def describe(name: str) -> str:
    """First line of the scene's docstring."""
    return (inspect.getdoc(_builder(name)) or "").splitlines()[0]


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
    builder = _builder(name)
    params = defaults(name)
    unknown = sorted(set(overrides) - set(params))
    if unknown:
        raise InputError(f"case {name} has no parameter {unknown[0]!r}; parameters: {', '.join(params)}.")
    values = {k: _coerce(name, k, v, params[k]) for k, v in overrides.items()}
    return builder(**values)
