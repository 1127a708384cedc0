"""Inflow buffer for gas SPH (SPEC §3.1; Lastiwka, Basa & Quinlan 2009,
Int. J. Numer. Meth. Fluids 61, 709).

A layer of buffer particles, at least ``depth`` (more than one support
radius) thick, sits upstream of an inflow side. Buffer particles carry the
imposed state (ρ, v, p) of the current time and move with the imposed
velocity; their density and support are imposed, not summed. A buffer
particle that crosses the inlet becomes a fluid particle; a new column is
spawned one spacing upstream of the last whenever the layer thins, so the
mass flux ρ v through the inlet is the imposed one (all particles have the
same mass m; columns are ``m / (ρ Δy)`` apart in 2D, ``m/ρ`` in 1D, and the
rows ``Δy ≈ sqrt(m/ρ(0))`` apart, so the layer starts isotropic).
"""

from __future__ import annotations

import numpy as np


class InflowBuffer:
    """The buffer layer of one inflow side (``x_lo`` for now)."""

    def __init__(self, scene, side: str, mass: float, depth: float):
        if side != "x_lo":
            raise ValueError(f"inflow buffers are implemented for side x_lo only, got {side}.")
        self.scene, self.mass, self.depth = scene, mass, depth
        self.state = scene.boundaries[side].state
        self.wall = scene.domain[0][0]
        self.dim = scene.dim
        if self.dim == 2:
            # rows as far apart as the columns at the imposed density of t = 0: an isotropic layer, so
            # the particles entering the domain do not have to rearrange (which would heat the gas)
            (y0, y1) = scene.domain[1]
            ny = max(1, int(round((y1 - y0) / np.sqrt(mass / self.state(0.0)[0]))))
            self.column_y = y0 + (np.arange(ny) + 0.5) * (y1 - y0) / ny
            self.dy = (y1 - y0) / ny
        else:
            self.column_y, self.dy = np.zeros(1), 1.0
        self.columns = np.zeros(0)  # x of every buffer column
        self._fill(0.0)

    def spacing(self, t: float) -> float:
        """Distance between columns at the imposed density of time ``t``."""
        rho = self.state(t)[0]
        return self.mass / (rho * self.dy)

    def _fill(self, t: float) -> None:
        """Add columns upstream until the layer is ``depth`` thick."""
        s = self.spacing(t)
        last = self.columns.min() if self.columns.size else self.wall + 0.5 * s
        new = []
        while last - s >= self.wall - self.depth:
            last -= s
            new.append(last)
        self.columns = np.concatenate([self.columns, new])

    def advance(self, t: float, dt: float) -> np.ndarray:
        """Move the layer over ``[t, t + dt]`` with the imposed velocity; return
        the positions (k, dim) of the particles that crossed into the domain."""
        u = self.state(t + 0.5 * dt)[1]
        self.columns = self.columns + dt * u
        crossed = self.columns >= self.wall
        entering = self.columns[crossed]
        self.columns = self.columns[~crossed & (self.columns >= self.wall - 2.0 * self.depth)]
        self._fill(t + dt)
        return self._positions(entering)

    def _positions(self, columns) -> np.ndarray:
        if self.dim == 1:
            return columns[:, None]
        X, Y = np.meshgrid(columns, self.column_y, indexing="ij")
        return np.stack([X.ravel(), Y.ravel()], axis=1)

    def particles(self, t: float, eta: float):
        """``(x, v, rho, u, H)`` of the buffer particles at time ``t``."""
        x = self._positions(self.columns)
        rho, u, v, p = self.state(t)
        k = x.shape[0]
        vel = np.tile(np.array([u, v][: self.dim]), (k, 1))
        H = eta * (self.mass / rho) ** (1.0 / self.dim)
        gamma = self.scene.gamma
        return x, vel, np.full(k, rho), np.full(k, p / ((gamma - 1.0) * rho)), np.full(k, H)
