"""Particle positions, box corners and periodic axes as the particle kernels take them, each checked
once at the entry of a public function with a one-sentence error naming the argument."""

from __future__ import annotations

import numpy as np

from partmesh.cases.errors import InputError

__all__ = ["box_corners", "ordered_box", "periodicity", "positions"]


def positions(x):
    """``x`` as a contiguous (n, dim) float array, dim 1, 2 or 3 (a 1D array is read as (n, 1)), finite."""
    try:
        x = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("x must be a numeric array of positions with shape (n, dim).") from None
    if x.ndim == 1:
        x = x[:, None]
    if x.ndim != 2 or x.shape[1] not in (1, 2, 3):
        raise InputError(f"x must have shape (n, dim) with dim 1, 2 or 3; got shape {x.shape}.")
    if not np.all(np.isfinite(x)):
        raise InputError("x (particle positions) must be finite; found NaN or inf.")
    return np.ascontiguousarray(x)


def box_corners(lo, hi, dim):
    """The box corners ``lo`` and ``hi``, each as ``dim`` finite floats; a single number stands for every axis."""
    return _corner("lo", lo, dim), _corner("hi", hi, dim)


def ordered_box(lo, hi, dim):
    """:func:`box_corners`, with ``hi`` above ``lo`` on every axis."""
    lo, hi = box_corners(lo, hi, dim)
    if np.any(hi <= lo):
        raise InputError(f"hi must exceed lo on every axis; got lo={lo.tolist()}, hi={hi.tolist()}.")
    return lo, hi


def _corner(name, value, dim):
    try:
        v = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be {dim} finite numbers (one per axis).") from None
    if v.size == 1 and dim > 1:
        v = np.repeat(v, dim)
    if v.size != dim or not np.all(np.isfinite(v)):
        raise InputError(f"{name} must be {dim} finite numbers (one per axis); got {value!r}.")
    return v


def periodicity(periodic, dim):
    """``periodic`` as ``dim`` booleans, one per axis; a single one stands for every axis."""
    p = np.asarray(periodic).reshape(-1)
    if p.size == 1 and dim > 1:
        p = np.repeat(p, dim)
    if p.size != dim or not all(isinstance(b, (bool, np.bool_)) or b in (0, 1) for b in p.tolist()):
        raise InputError(f"periodic must be {dim} booleans (one per axis); got {periodic!r}.")
    return p.astype(np.bool_)
