"""The Pareto front of runs measured by cost and error: the runs worth
their cost in a speed-versus-error study (SPEC §5)."""

from __future__ import annotations

import numpy as np


def pareto_front(seconds, errors) -> np.ndarray:
    """Mask of the runs no other run beats in both cost and error: run i is
    on the front unless some run j has seconds_j ≤ seconds_i and errors_j ≤
    errors_i with one of them strictly less (NaN entries are never on it)."""
    seconds, errors = np.asarray(seconds, float), np.asarray(errors, float)
    if seconds.shape != errors.shape or seconds.ndim != 1:
        raise ValueError("seconds and errors must be 1D arrays of one length.")
    valid = np.isfinite(seconds) & np.isfinite(errors)
    front = np.zeros(seconds.size, dtype=bool)
    for i in np.flatnonzero(valid):
        no_worse = valid & (seconds <= seconds[i]) & (errors <= errors[i])
        better = no_worse & ((seconds < seconds[i]) | (errors < errors[i]))
        front[i] = not better.any()
    return front
