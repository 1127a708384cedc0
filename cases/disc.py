"""The initial disc (or, in 3D, ball) of a point blast (``sedov``,
``blast_kt``, ``sedov_3d``): the fraction of each cell inside it and the
energy or mass density that deposits a total over it exactly on a lattice
of cells."""

from __future__ import annotations

from functools import reduce

import numpy as np

#: sub-samples per cell side
SUB = 8


def disc_fraction(x, y, radius: float, dx: float, z=None) -> np.ndarray:
    """The fraction of each square (with ``z``: cubic) cell of side ``dx``
    centred at ``(x, y[, z])`` that lies within ``radius`` of the origin,
    from 8×8 (8×8×8) sub-samples."""
    points = [np.asarray(c, float) for c in ((x, y) if z is None else (x, y, z))]
    sub = (np.arange(SUB) + 0.5) / SUB - 0.5
    offsets = [o.ravel() for o in np.meshgrid(*[sub * dx] * len(points))]
    points = np.broadcast_arrays(*points)
    near = reduce(np.hypot, points) < radius + dx
    fraction = np.zeros(points[0].shape)
    fraction[near] = (reduce(np.hypot, [c[near][:, None] + o for c, o in zip(points, offsets)]) < radius).mean(axis=1)
    return fraction


def disc_density(x, y, radius: float, dx: float, z=None) -> np.ndarray:
    """A deposit spread over the disc (with ``z``: ball) of ``radius`` at the origin, per unit
    area (volume) and per unit of the total: :func:`disc_fraction` divided by its
    integral Σ f dx^d over the lattice of cells of side ``dx`` with edges
    on the axes. On such a lattice (or any part of it: a quadrant) the
    deposit sums to the total to round-off; the value at a point depends on
    that point alone, so a subset of points (a boundary sample, particles
    laid out in pieces) gets the same values."""
    n = int(np.ceil(radius / dx)) + 1
    centres = (np.arange(-n, n) + 0.5) * dx
    dim = 2 if z is None else 3
    lattice = np.meshgrid(*[centres] * dim)
    volume = disc_fraction(*lattice[:2], radius, dx, *lattice[2:]).sum() * dx * dx * (dx if dim == 3 else 1.0)
    return disc_fraction(x, y, radius, dx, z) / volume
