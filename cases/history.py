"""What a run records step by step, resampled onto the scene's probe times.

Every solver, whatever its method, records after each step the pressure at
the scene's probes and the force the gas exerts on each side of the domain;
:class:`History` turns those records into the schema's ``p_probe``,
``wall_force`` and ``wall_impulse`` on the scene's ``t_probe``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class History:
    """Per-step records of one run.

    ``record(t0, dt, probes, side_forces)`` stores the probe values at the end
    of the step ``[t0, t0 + dt]`` and the time-centred force on every side
    over it (per metre depth in 2D, per square metre in 1D); the impulse is
    accumulated exactly as Σ force·dt.
    """

    probes0: np.ndarray
    n_sides: int
    t: list = field(default_factory=lambda: [0.0])
    probes: list = field(default_factory=list)
    force_t: list = field(default_factory=list)
    forces: list = field(default_factory=list)
    impulses: list = field(default_factory=list)

    def __post_init__(self):
        self.probes = [np.asarray(self.probes0, float)]
        self.impulses = [np.zeros(self.n_sides)]

    def record(self, t0: float, t1: float, probes, side_forces) -> None:
        forces = np.asarray(side_forces, float)
        self.force_t.append(0.5 * (t0 + t1))
        self.forces.append(forces)
        self.impulses.append(self.impulses[-1] + (t1 - t0) * forces)
        self.t.append(t1)
        self.probes.append(np.asarray(probes, float))

    def series(self, scene, t_probe: np.ndarray) -> dict:
        """The schema's time series of ``scene`` on ``t_probe``: ``p_probe``
        (if the scene has probes) and ``wall_force``/``wall_impulse`` (if it
        has a target wall), the force relative to the ambient ``p0``."""
        out = {}
        if scene.probes:
            samples = np.stack(self.probes)
            out["p_probe"] = np.stack([np.interp(t_probe, self.t, s) for s in samples.T], axis=1)
        if scene.wall is not None and self.forces:
            side = scene.sides.index(scene.wall.side)
            if scene.dim == 1:
                scale, ambient = scene.wall.height, scene.wall.p0
            else:
                lo, hi = scene.domain[1 - side // 2]
                scale, ambient = 1.0, scene.wall.p0 * (hi - lo)
            force = (np.stack(self.forces)[:, side] - ambient) * scale
            impulse = (np.stack(self.impulses)[:, side] - ambient * np.asarray(self.t)) * scale
            out["wall_force"] = np.interp(t_probe, self.force_t, force)
            out["wall_impulse"] = np.interp(t_probe, self.t, impulse)
        return out
