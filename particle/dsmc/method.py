"""Method ``dsmc``: its settings and its entry in the method registry
(:mod:`partmesh.cases.method`); the solver is :mod:`partmesh.particle.dsmc.solve`."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from partmesh.cases.checks import positive
from partmesh.cases.errors import InputError, Unsupported
from partmesh.cases.memory import elements_in
from partmesh.cases.method import Memory, Method
from partmesh.cases.settings import Settings, at_least, one_of, setting, within
from partmesh.particle.dsmc.intervals import REDRAWS
from partmesh.particle.dsmc.profile import PROFILES

#: what happens in a cell over a step: the equilibrium redraw, or VHS collisions with Larsen–Borgnakke exchange
COLLISIONS = ("equilibrium", "larsen-borgnakke")
#: the settings of collisions="larsen-borgnakke" only
COLLISION_MODEL = ("mean_free_path", "omega", "z_rot")
#: bytes a particle takes: position, three velocities, internal energy, cell and sort keys
PARTICLE_BYTES = 120.0


#: the largest seed: the kernels take it as a 64-bit signed integer
MAX_SEED = 2**63 - 1


@dataclass(frozen=True)
class DSMCSettings(Settings):
    """Settings of equilibrium DSMC on cells of size ``dx``: ``ppc``
    particles per cell in the lowest-density initial state set the particle
    mass; ``seed`` makes the run reproducible (bit-identical on the same
    machine, whatever the thread count); ``window`` is the number of steps
    whose moments are averaged into each output frame. ``cfl`` = 1 lets a
    particle 3σ faster than its cell's flow cross one cell per step; on
    ``sod`` at 400 cells it leaves the first-order (EFM) dissipation lower
    than 0.5 does (L1 1.6e-2 against 1.8e-2, 30 particles per cell x 16
    ensembles). ``collisions="larsen-borgnakke"`` needs ``mean_free_path``
    [m] at the lowest initial density; ``omega`` (VHS viscosity exponent)
    and ``z_rot`` (rotational collision number) apply to it.
    ``profile="linear"`` redraws each cell about the limited linear profiles
    of its mean velocity and temperature instead of their cell values
    (:mod:`partmesh.particle.dsmc.profile`): less dissipation for about half
    again the cost of a step. ``redraw="local"`` redraws each cell at its
    own Courant step, a multiple of the global one set by the fastest cell,
    instead of every step (:mod:`partmesh.particle.dsmc.intervals`): less
    dissipation in gas much slower than the fastest, and fewer draws. In an
    axisymmetric scene ``ppc`` is the count of every ring cell of the
    lowest initial density (radial weights)."""

    method: ClassVar[str] = "dsmc"

    ppc: int = setting(30, at_least(1), "particles per cell, at least 1")
    cfl: float = setting(1.0, within(0.0, 1.0, lo_open=True),
                         "Courant number in (0, 1]")
    seed: int = setting(0, at_least(0, MAX_SEED), f"random seed, 0 to {MAX_SEED}")
    window: int = setting(1, at_least(1), "steps averaged into a frame, at least 1")
    collisions: str = setting("equilibrium", one_of(COLLISIONS), "collision model")
    profile: str = setting("uniform", one_of(PROFILES), "mean velocity across a cell in the redraw")
    redraw: str = setting("every-step", one_of(REDRAWS), "when a cell is redrawn")
    mean_free_path: float | None = setting(None, positive, "mean free path at the lowest initial density [m]")
    omega: float = setting(0.74, within(0.5, 1.0),
                           "VHS viscosity exponent, in [0.5, 1]")
    z_rot: float = setting(5.0, within(1.0, math.inf),
                           "rotational collision number, at least 1")

    def check_together(self, scene) -> None:
        super().check_together(scene)
        if scene.obstacles and scene.dim != 2:
            raise Unsupported(f"scene {scene.name}: dsmc models obstacles in 2D only.")
        if scene.geometry == "axisymmetric" and scene.obstacles:
            raise Unsupported(f"scene {scene.name}: dsmc models obstacles in planar scenes only (a molecule's "
                              "straight flight is a curve in the r-z plane).")
        if scene.geometry == "axisymmetric" and self.collisions != "equilibrium":
            raise Unsupported(f"scene {scene.name}: dsmc runs axisymmetric scenes with collisions='equilibrium' only "
                              "(the redraw resamples the radial weights).")
        if self.collisions == "larsen-borgnakke" and self.mean_free_path is None:
            raise InputError("collisions='larsen-borgnakke' needs mean_free_path, the mean free path [m] > 0 at the "
                             "scene's lowest initial density.")
        if self.collisions != "equilibrium" and self.profile != "uniform":
            raise InputError(f"profile={self.profile!r} applies only to collisions='equilibrium' (true collisions "
                             "keep each particle's velocity).")
        if self.collisions != "equilibrium" and self.redraw != "every-step":
            raise InputError(f"redraw={self.redraw!r} applies only to collisions='equilibrium' (true collisions "
                             "happen at their rate in every cell every step).")
        if self.collisions != "larsen-borgnakke" and self.mean_free_path is not None:
            raise InputError("mean_free_path applies only to collisions='larsen-borgnakke'; the equilibrium redraw "
                             "has none (it is the limit of a vanishing mean free path).")

    def record(self) -> dict:
        """The settings a result keeps (those of the collision model only
        with collisions="larsen-borgnakke")."""
        record = super().record()
        if self.collisions != "larsen-borgnakke":
            for name in COLLISION_MODEL:
                del record[name]
        return record


def memory(scene, settings: DSMCSettings) -> Memory:
    return Memory(elements_in(scene.domain, settings.dx) * settings.ppc, PARTICLE_BYTES, "particles",
                  "dx or lower ppc")


METHOD = Method("dsmc", "gas", DSMCSettings, memory, "partmesh.particle.dsmc.solve:solve", takes_seed=True,
                geometries=("planar", "axisymmetric"), dims=(1, 2, 3))
