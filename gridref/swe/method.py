"""Method ``swe``: its settings and its entry in the method registry
(:mod:`partmesh.cases.method`); the solver is :mod:`partmesh.gridref.swe.solve`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from partmesh.cases.memory import elements_in, grid_cell_bytes
from partmesh.cases.method import Memory, Method
from partmesh.cases.settings import Settings, one_of, setting, within
from partmesh.gridref.euler.method import LIMITER_NAMES

#: the array precisions of :data:`partmesh.gridref.swe.step.PRECISIONS`
PRECISION_NAMES = ("float64", "float32")


@dataclass(frozen=True)
class SWESettings(Settings):
    """Settings of the shallow-water model: ``dx`` the cell size [m],
    ``cfl`` the Courant number (the depth stays ≥ 0 up to 0.25,
    :mod:`partmesh.gridref.swe.step`), ``limiter`` the slope limiter of depth,
    surface and velocity, ``precision`` "float64" or "float32" (about three
    times the speed on a CPU, for long runs whose waves are much larger
    than 1e-6 of the depth)."""

    method: ClassVar[str] = "swe"

    cfl: float = setting(0.25, within(0.0, 0.5, lo_open=True),
                         "Courant number in (0, 0.5]")
    limiter: str = setting("mc", one_of(LIMITER_NAMES), "slope limiter")
    precision: str = setting("float64", one_of(PRECISION_NAMES), "array precision")


def memory(scene, settings: SWESettings) -> Memory:
    return Memory(elements_in(scene.domain, settings.dx), grid_cell_bytes(scene.dim + 1, scene), "cells")


METHOD = Method("swe", "water", SWESettings, memory, "partmesh.gridref.swe.solve:solve")
