"""Method ``hybrid``: its settings and its entry in the method registry
(:mod:`partmesh.cases.method`); the solver is :mod:`partmesh.hybrid.solve`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from partmesh.cases.checks import positive
from partmesh.cases.errors import InputError
from partmesh.cases.memory import elements_in, grid_cell_bytes
from partmesh.cases.method import Memory, Method
from partmesh.cases.settings import at_least, one_of, setting, within
from partmesh.gridref.euler.method import LIMITER_NAMES, RIEMANN_NAMES
from partmesh.hybrid.cells import SENSORS
from partmesh.particle.sph.method import SPHScheme

#: the most particles per cell width (beta = 1/k)
MOST_PER_CELL = 16


@dataclass(frozen=True)
class HybridSettings(SPHScheme):
    """Settings of the hybrid finite-volume – SPH method: ``dx`` the
    particle spacing [m], ``beta`` the ratio of particle spacing to cell
    width (1/k for a whole k: the grid's cells are ``dx / beta`` wide),
    ``threshold`` the relative jump between neighbouring cells above which
    a cell gets particles — of density or pressure (``sensor="rho,p"``:
    shocks and contacts), of pressure alone (``"p"``: contacts stay on the
    grid) or of pressure across compressing faces (``"shock"``: only shocks
    hold particles) — ``buffer`` the cells added around those, ``cfl`` the
    grid's Courant number, ``cfl_sph`` the particles' (Δt = C min h/v_sig);
    the SPH scheme's settings are those of method ``sph``
    (:class:`~partmesh.particle.sph.method.SPHScheme`), ``limiter`` and ``riemann``
    those of ``fv``."""

    method: ClassVar[str] = "hybrid"

    beta: float = setting(0.25, within(0.0, 1.0, lo_open=True),
                          "particle spacing over cell width, 1/k")
    threshold: float = setting(0.05, positive, "relative jump that gives a cell particles, > 0")
    sensor: str = setting("rho,p", one_of(SENSORS), "what the jump is of")
    buffer: int = setting(2, at_least(0), "cells added around flagged ones, at least 0")
    cfl: float = setting(0.8, within(0.0, 1.0, lo_open=True), "the grid's Courant number in (0, 1]")
    cfl_sph: float = setting(0.25, within(0.0, 1.0, lo_open=True),
                             "the particles' Courant number in (0, 1]")
    limiter: str = setting("mc", one_of(LIMITER_NAMES), "the grid's slope limiter")
    riemann: str = setting("hllc", one_of(RIEMANN_NAMES), "the grid's Riemann solver")

    @property
    def per_cell(self) -> int:
        """Particles per cell width, 1/beta."""
        return int(round(1.0 / self.beta))

    def check_together(self, scene) -> None:
        super().check_together(scene)
        if abs(self.per_cell * self.beta - 1.0) > 1e-9 or self.per_cell > MOST_PER_CELL:
            raise InputError(f"beta must be 1/k for a whole k from 1 to {MOST_PER_CELL} (particles per cell width); "
                             f"got {self.beta:g}.")
        if scene.obstacles:
            raise InputError(f"method hybrid runs scenes without obstacles; {scene.name} has {len(scene.obstacles)}.")


def memory(scene, settings: HybridSettings) -> Memory:
    """The grid's share; the particles live only in the cells the sensor flags."""
    return Memory(elements_in(scene.domain, settings.dx / settings.beta), grid_cell_bytes(scene.dim + 2, scene),
                  "grid cells")


METHOD = Method("hybrid", "gas", HybridSettings, memory, "partmesh.hybrid.solve:solve")
