"""Method ``wcsph``: its settings and its entry in the method registry
(:mod:`partmesh.cases.method`); the solver is :mod:`partmesh.particle.wcsph.solve`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from partmesh.cases.checks import positive
from partmesh.cases.memory import elements_in, particle_bytes
from partmesh.cases.method import Memory, Method
from partmesh.cases.settings import Settings, optional_path, setting, within


@dataclass(frozen=True)
class WCSPHSettings(Settings):
    """Settings of weakly compressible SPH in a vertical slice: ``dx`` the
    particle spacing [m] (None: a 25th of the depth), ``cfl`` the Courant
    number, ``c0`` the numerical sound speed as a multiple of sqrt(g d_max)
    (d_max the deepest initial water), ``alpha`` the Monaghan viscosity,
    ``delta`` the density-diffusion coefficient (0: none), ``eta`` the
    kernel support H in units of dx (H = 2h; 4 gives h = 2 dx: at h = √2 dx
    a standing wave 25 particles deep swings 6 % fast, at 2 dx within
    1 %), ``damping`` the length of the damping zone before an absorbing
    x_hi (None: a fifth of the flume), ``particles`` a file to write the
    last state's particles to."""

    method: ClassVar[str] = "wcsph"

    cfl: float = setting(0.2, within(0.0, 0.4, lo_open=True), "Courant number in (0, 0.4]")
    c0: float = setting(10.0, within(3.0, 40.0), "sound speed in units of sqrt(g d_max), in [3, 40]")
    alpha: float = setting(0.01, within(0.0, 1.0), "Monaghan viscosity, in [0, 1]")
    delta: float = setting(0.1, within(0.0, 1.0), "density-diffusion coefficient, in [0, 1]")
    eta: float = setting(4.0, within(2.0, 4.0), "kernel support in units of dx, in [2, 4]")
    damping: float | None = setting(None, positive, "length of the damping zone [m]")
    particles: str | None = setting(None, optional_path, "file for the particles of the last state")

    def scene_defaults(self, scene) -> dict:
        return {**super().scene_defaults(scene), "dx": scene.depth / 25.0 if self.dx is None else self.dx}


def memory(scene, settings: WCSPHSettings) -> Memory:
    return Memory(elements_in(scene.domain, settings.dx) * scene.depth / settings.dx,
                  particle_bytes(2, 1.25 * settings.eta), "particles")


METHOD = Method("wcsph", "water", WCSPHSettings, memory, "partmesh.particle.wcsph.solve:solve")
