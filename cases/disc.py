"""The initial disc of a point blast (``sedov``, ``blast_kt``): the fraction
of each cell inside it and the energy or mass density that deposits a
total over it exactly on a lattice of cells."""

from __future__ import annotations

import numpy as np


def disc_fraction(x, y, radius: float, dx: float) -> np.ndarray:
    """The fraction of each square cell of side ``dx`` centred at ``(x, y)``
    that lies within ``radius`` of the origin, from 8×8 sub-samples."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    sub = (np.arange(8) + 0.5) / 8 - 0.5
    sx, sy = np.meshgrid(sub * dx, sub * dx)
    near = np.hypot(x, y) < radius + dx
    fraction = np.zeros(np.broadcast(x, y).shape)
    fraction[near] = (np.hypot(x[near][:, None] + sx.ravel(), y[near][:, None] + sy.ravel()) < radius).mean(axis=1)
    return fraction


def disc_density(x, y, radius: float, dx: float) -> np.ndarray:
    """A deposit spread over the disc of ``radius`` at the origin, per unit
    area and per unit of the total: :func:`disc_fraction` divided by its
    integral Σ f dx² over the lattice of cells of side ``dx`` with edges
    on the axes. On such a lattice (or any part of it: a quadrant) the
    deposit sums to the total to round-off; the value at a point depends on
    that point alone, so a subset of points (a boundary sample, particles
    laid out in pieces) gets the same values."""
    n = int(np.ceil(radius / dx)) + 1
    centres = (np.arange(-n, n) + 0.5) * dx
    area = disc_fraction(*np.meshgrid(centres, centres), radius, dx).sum() * dx * dx
    return disc_fraction(x, y, radius, dx) / area
