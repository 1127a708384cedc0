"""Input validation shared by every partmesh package: one clear sentence
naming the parameter and the allowed range, raised as :class:`InputError`
before any work starts (SPEC §9)."""

from __future__ import annotations

import math


class InputError(ValueError):
    """A parameter outside its allowed range."""


def number(name: str, value) -> float:
    """``value`` as a finite float."""
    try:
        as_float = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a finite number, got {value!r}.") from None
    if not math.isfinite(as_float):
        raise InputError(f"{name} must be a finite number, got {value!r}.")
    return as_float


def positive(name: str, value) -> float:
    """``value`` as a float, which must be finite and > 0."""
    value = number(name, value)
    if not value > 0:
        raise InputError(f"{name} must be a finite number > 0, got {value:g}.")
    return value


def non_negative(name: str, value) -> float:
    """``value`` as a float, which must be finite and >= 0."""
    value = number(name, value)
    if value < 0:
        raise InputError(f"{name} must be a finite number >= 0, got {value:g}.")
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


def flag(name: str, value) -> bool:
    """``value`` as a bool: a bool, 0 or 1, or the text true/false, yes/no,
    on/off, 1/0 (any case), as a setting given on the command line is."""
    words = {"true": True, "yes": True, "on": True, "1": True, "false": False, "no": False, "off": False, "0": False}
    if isinstance(value, str) and value.strip().lower() in words:
        return words[value.strip().lower()]
    if not isinstance(value, str) and value in (True, False):
        return bool(value)
    raise InputError(f"{name} must be true or false, got {value!r}.")


def choice(name: str, value, options) -> str:
    """``value``, which must be one of ``options``."""
    if value not in options:
        raise InputError(f"{name} must be one of {', '.join(map(str, options))}; got {value!r}.")
    return value


def integer(name: str, value, lo: int, hi: int | None = None) -> int:
    """``value`` as an int ≥ lo (and ≤ hi)."""
    try:
        as_int = int(value)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{name} must be an integer, got {value!r}.") from None
    if as_int != value and not (isinstance(value, str) and str(as_int) == value.strip()):
        raise InputError(f"{name} must be an integer, got {value!r}.")
    if as_int < lo or (hi is not None and as_int > hi):
        upper = "" if hi is None else f" and at most {hi}"
        raise InputError(f"{name} must be at least {lo}{upper}, got {as_int}.")
    return as_int
