"""The drift of a conserved total over a run."""

from __future__ import annotations

import numpy as np


def conservation_drift(totals) -> float:
    """Relative drift of a conserved total: max_t |q(t) − q(0)| / |q(0)|.

    ``totals`` is the time history of a domain integral (mass, momentum,
    energy) of a closed-domain run; the drift should sit at round-off for
    the conservative FV and DSMC schemes (SPEC §9).

    Raises
    ------
    ValueError
        for an empty or non-1D array, non-finite entries, or q(0) = 0.
    """
    q = np.asarray(totals, dtype=float)
    if q.ndim != 1 or q.size < 1:
        raise ValueError(f"totals must be a non-empty 1D array, got shape {q.shape}.")
    if not np.all(np.isfinite(q)):
        raise ValueError("totals must be finite (it holds NaN or inf).")
    if q[0] == 0.0:
        raise ValueError("totals[0] must be non-zero (the drift is relative to it).")
    return float(np.max(np.abs(q - q[0])) / abs(q[0]))
