"""Input checks and small helpers shared by the exact solutions.

Every check raises :class:`ValueError` with one sentence that names the
parameter and the allowed range (SPEC §9).
"""

from __future__ import annotations

import numpy as np

from partmesh.compare.checks import non_negative, positive

__all__ = ["GEOMETRIES", "axis", "geometry_index", "internal_energy", "non_negative", "output_times", "positive",
           "ratio_of_heats"]

#: geometry name -> j, the number of symmetric dimensions (1 planar, 2 cylindrical, 3 spherical)
GEOMETRIES = {"planar": 1, "cylindrical": 2, "spherical": 3}


def ratio_of_heats(gamma) -> float:
    """The ratio of specific heats, which must be finite and > 1."""
    gamma = float(gamma)
    if not np.isfinite(gamma) or gamma <= 1.0:
        raise ValueError(f"gamma must be a finite number > 1, got {gamma}.")
    return gamma


def geometry_index(geometry: str) -> int:
    """j = 1, 2, 3 for ``"planar"``, ``"cylindrical"``, ``"spherical"``."""
    if geometry not in GEOMETRIES:
        raise ValueError(f"geometry must be one of {', '.join(GEOMETRIES)}, got {geometry!r}.")
    return GEOMETRIES[geometry]


def axis(name: str, values) -> np.ndarray:
    """A 1D, finite, strictly increasing coordinate with at least two points."""
    values = np.asarray(values, dtype=float)
    if values.ndim != 1 or values.size < 2 or not np.all(np.isfinite(values)) or np.any(np.diff(values) <= 0):
        raise ValueError(f"{name} must be a 1D, finite, strictly increasing array of at least 2 points.")
    return values


def output_times(times, *, allow_zero: bool = True) -> np.ndarray:
    """A 1D, finite, strictly increasing array of output times, all >= 0 (> 0 if not ``allow_zero``)."""
    times = np.atleast_1d(np.asarray(times, dtype=float))
    if (times.ndim != 1 or times.size == 0 or not np.all(np.isfinite(times))
            or np.any(np.diff(times) <= 0) or np.any(times < 0) or (not allow_zero and np.any(times == 0))):
        raise ValueError("times must be a non-empty, finite, strictly increasing 1D array of values "
                         f"{'>=' if allow_zero else '>'} 0.")
    return times


def internal_energy(p: np.ndarray, rho: np.ndarray, gamma: float) -> np.ndarray:
    """e = p / ((gamma - 1) rho); 0 where p = 0 (vacuum) and inf where only rho = 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        e = p / ((gamma - 1.0) * rho)
    return np.where(p == 0.0, 0.0, e)
