"""Method ``fv``: its settings and its entry in the method registry
(:mod:`partmesh.cases.method`); the solver is :mod:`partmesh.gridref.euler.solve`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from partmesh.cases.memory import elements_in, grid_cell_bytes
from partmesh.cases.method import Memory, Method
from partmesh.cases.settings import Settings, one_of, setting, within

#: the slope limiters of :mod:`partmesh.gridref.euler.reconstruct` and the Riemann solvers of :mod:`partmesh.gridref.euler.riemann`
LIMITER_NAMES = ("minmod", "mc", "vanleer", "superbee", "first_order")
RIEMANN_NAMES = ("hllc", "hll", "rusanov", "efm")


@dataclass(frozen=True)
class FVSettings(Settings):
    """Settings of the unsplit MUSCL–Hancock finite-volume scheme: ``dx``
    the cell size [m], ``cfl`` the Courant number, ``limiter`` the slope
    limiter, ``riemann`` the Riemann solver."""

    method: ClassVar[str] = "fv"

    cfl: float = setting(0.8, within(0.0, 1.0, lo_open=True), "Courant number in (0, 1]")
    limiter: str = setting("mc", one_of(LIMITER_NAMES), "slope limiter")
    riemann: str = setting("hllc", one_of(RIEMANN_NAMES), "Riemann solver")


def memory(scene, settings: FVSettings) -> Memory:
    return Memory(elements_in(scene.domain, settings.dx), grid_cell_bytes(scene.dim + 2, scene), "cells")


METHOD = Method("fv", "gas", FVSettings, memory, "partmesh.gridref.euler.solve:solve",
                geometries=("planar", "axisymmetric", "spherical"))
