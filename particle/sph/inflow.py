"""Inflow buffer for gas SPH (SPEC §3.1; Lastiwka, Basa & Quinlan 2009,
Int. J. Numer. Meth. Fluids 61, 709).

A layer of buffer particles, ``depth`` (more than one support radius) thick,
sits upstream of an inflow side. Buffer particles carry the boundary state
(ρ, v, p) of the current time; their density and support are imposed, not
summed. The layer is a square lattice at the boundary density ρ: rows
``Δy ≈ sqrt(m/ρ)`` apart (re-laid as ρ changes; one row in 1D) and columns
of mass per unit inlet width ``μ = m/Δy`` (``m`` in 1D), ``μ/ρ = Δy`` apart.
With ``Φ = ∫ ρ u dt`` the mass per unit width that has flowed through the
inlet and ``E`` the mass per unit width the columns that entered carried,
column ``k = 0, 1, ...`` sits at ``x_k = x_inlet − ((k + ½) μ − (Φ − E))/ρ``.
The lattice moves with the boundary velocity; the first column crosses the
inlet and becomes fluid particles when ``Φ − E`` reaches ``½ μ`` (then
``E += μ``), so the mass that enters is the boundary mass flux to within
one column however the density varies. Where the boundary state flows out
of the domain the lattice moves upstream, fluid particles that cross the
inlet leave the run, no column enters, and the layer stays at the inlet
(``E −= μ`` when ``Φ − E`` falls below ``−½ μ``).

The lattice must stay square: a layer whose rows keep the spacing of the
blast's peak density (four times the ambient) while its columns spread to
four times that at the end of the positive phase holds the gas at the
inlet with too few columns in a support, and lets an expansion run away
there (2D ``blast_wall`` at 2 mm: the density at the inlet fell to 0.04
ρ0 by 0.63 ms).

The boundary state is the one a finite-volume scheme puts on the inlet face
(:func:`~partmesh.cases.inlet.inlet_face_state`; Toro 2009, §6.3.3): the
exact solution at x/t = 0 of the Riemann problem between the imposed state
(upstream) and the gas next to the inlet (downstream). Where the imposed flow is supersonic it is the imposed state;
where it is subsonic, the waves travelling upstream from the domain (the
blast's reflection from the far wall, the expansion behind a decaying blast)
leave through the inlet instead of reflecting from a layer that holds its
pressure and velocity fixed. A shock entering gas at rest, as in
``shock_reflection``, has exactly the imposed state on the inlet face.
"""

from __future__ import annotations

import numpy as np

from partmesh.cases.inlet import inlet_face_state


class InflowBuffer:
    """The buffer layer of one inflow side (``x_lo`` for now)."""

    def __init__(self, scene, side: str, mass: float, depth: float):
        if side != "x_lo":
            raise ValueError(f"inflow buffers are implemented for side x_lo only, got {side}.")
        self.scene, self.mass, self.depth = scene, mass, depth
        self.imposed = scene.boundaries[side].state
        self.wall = scene.domain[0][0]
        self.dim = scene.dim
        (y0, y1) = scene.domain[1] if self.dim == 2 else (0.0, 1.0)
        self.y0, self.width = y0, y1 - y0
        #: (ρ, u, v, p) of the gas next to the inlet, None until observed
        self.adjacent = None
        #: Φ and E (see the module docstring): the mass per unit inlet width that has flowed in
        #: (negative where it flowed out), and that the columns which entered carried
        self.inflowed = self.entered = 0.0
        self._last_state = (None, None)  # ((t, adjacent), state): a step asks for the same state several times

    def rows(self, rho: float) -> np.ndarray:
        """y of the rows of a square lattice of particles of mass m at density ``rho``."""
        if self.dim == 1:
            return np.zeros(1)
        ny = max(1, int(round(self.width / np.sqrt(self.mass / rho))))
        return self.y0 + (np.arange(ny) + 0.5) * self.width / ny

    def column_mass(self, rho: float) -> float:
        """μ: the mass per unit inlet width of a column of the lattice at density ``rho``."""
        return self.mass * (len(self.rows(rho)) / self.width if self.dim == 2 else 1.0)

    def state(self, t: float) -> tuple[float, float, float, float]:
        """``(ρ, u, v, p)`` on the inlet face at time ``t``: the Riemann
        problem of the imposed state and the adjacent gas sampled at x/t = 0;
        the tangential velocity is the upstream side's where the gas flows in."""
        key, state = self._last_state
        if key != (t, self.adjacent):
            state = self._face_state(t)
            self._last_state = ((t, self.adjacent), state)
        return state

    def _face_state(self, t: float) -> tuple[float, float, float, float]:
        imposed = self.imposed(t)
        if self.adjacent is None:
            return imposed
        return inlet_face_state(imposed, self.adjacent, self.scene.gamma)

    def observe(self, x, v, rho, p, width: float) -> None:
        """Take the adjacent gas as the mean state of the fluid particles
        within ``width`` of the inlet (unchanged if there are none)."""
        near = x[:, 0] < self.wall + width
        if near.any():
            vel = v[near].mean(axis=0)
            self.adjacent = (float(rho[near].mean()), float(vel[0]), float(vel[1]) if self.dim == 2 else 0.0,
                             float(p[near].mean()))

    def support(self, t: float, eta: float) -> float:
        """Support radius H = η (m/ρ)^(1/d) of the buffer particles at ``t``."""
        return eta * (self.mass / self.state(t)[0]) ** (1.0 / self.dim)

    def _columns(self, rho: float) -> np.ndarray:
        """x of the columns upstream of the inlet at boundary density ``rho``,
        the last within one column of the layer's depth. Their count depends
        on ``rho`` only, not on how far the layer has moved, so that it stays
        the same while a column crosses the inlet (and the neighbour lists
        can be kept: :meth:`partmesh.particle.sph.lists.VerletLists.reusable`)."""
        mu = self.column_mass(rho)
        ahead = self.inflowed - self.entered
        k = np.arange(int(np.floor(self.depth * rho / mu)) + 1)
        return self.wall - ((k + 0.5) * mu - ahead) / rho

    def advance(self, t: float, dt: float) -> np.ndarray:
        """Move the layer over ``[t, t + dt]`` with the boundary mass flux; return
        the positions (k, dim) at ``t + dt`` of the particles that crossed into the domain."""
        (rho0, u0, _, _), (rho1, u1, _, _) = self.state(t), self.state(t + dt)
        self.inflowed += 0.5 * (rho0 * u0 + rho1 * u1) * dt  # the trapezoidal rule
        mu = self.column_mass(rho1)
        crossed = []
        while self.inflowed - self.entered >= 0.5 * mu:
            crossed.append(self.wall + (self.inflowed - self.entered - 0.5 * mu) / rho1)
            self.entered += mu
        while self.inflowed - self.entered < -0.5 * mu:  # flowing out: the layer keeps to the inlet
            self.entered -= mu
        return self._positions(np.asarray(crossed, float), rho1)

    def _positions(self, columns, rho: float) -> np.ndarray:
        if self.dim == 1:
            return columns[:, None]
        X, Y = np.meshgrid(columns, self.rows(rho), indexing="ij")
        return np.stack([X.ravel(), Y.ravel()], axis=1)

    def particles(self, t: float, eta: float):
        """``(x, v, rho, u, H)`` of the buffer particles at time ``t``."""
        rho, u, v, p = self.state(t)
        x = self._positions(self._columns(rho), rho)
        k = x.shape[0]
        vel = np.tile(np.array([u, v][: self.dim]), (k, 1))
        gamma = self.scene.gamma
        return (x, vel, np.full(k, rho), np.full(k, p / ((gamma - 1.0) * rho)),
                np.full(k, self.support(t, eta)))
