"""Method ``fv``: its settings and its entry in the method registry
(:mod:`partmesh.cases.method`); the solver is :mod:`partmesh.gridref.euler.solve`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from partmesh.cases.errors import InputError
from partmesh.cases.memory import elements_in, grid_cell_bytes
from partmesh.cases.method import Memory, Method
from partmesh.cases.scene import Inflow
from partmesh.cases.settings import Settings, at_least, one_of, setting, within
from partmesh.gridref.amr.layout import layout_for

#: the slope limiters of :mod:`partmesh.gridref.euler.reconstruct` and the Riemann solvers of :mod:`partmesh.gridref.euler.riemann`
LIMITER_NAMES = ("minmod", "mc", "vanleer", "superbee", "first_order")
RIEMANN_NAMES = ("hllc", "hll", "rusanov", "efm")
#: the most refinement levels a run may ask for (a ratio of 2^11 between the coarsest and finest cells)
MAX_LEVELS = 12


@dataclass(frozen=True)
class FVSettings(Settings):
    """Settings of the unsplit MUSCL–Hancock finite-volume scheme: ``dx``
    the cell size [m], ``cfl`` the Courant number, ``limiter`` the slope
    limiter, ``riemann`` the Riemann solver."""

    method: ClassVar[str] = "fv"

    cfl: float = setting(0.8, within(0.0, 1.0, lo_open=True), "Courant number in (0, 1]")
    limiter: str = setting("mc", one_of(LIMITER_NAMES), "slope limiter")
    riemann: str = setting("hllc", one_of(RIEMANN_NAMES), "Riemann solver")
    levels: int = setting(1, at_least(1, MAX_LEVELS), "refinement levels of ratio 2, dx the finest (1: a uniform grid)")
    refine: float = setting(0.8, within(0.0, 1.0, lo_open=True, hi_open=True),
                            "Lohner estimate above which a cell asks for the next finer level, in (0, 1)")
    derefine: float = setting(0.2, within(0.0, 1.0, lo_open=True, hi_open=True),
                              "Lohner estimate above which a refined region is kept, in (0, refine]")
    gradient: float = setting(0.01, within(0.0, 1.0, lo_open=True),
                              "relative variation across a cell above which it asks for the next finer level, "
                              "in (0, 1]")
    block: int | None = setting(None, at_least(4, 256), "cells per block side (None: chosen to tile the grid)")

    def check_together(self, scene) -> None:
        super().check_together(scene)
        if scene.detonation is not None:
            if self.riemann != "hllc":
                raise InputError(f"{scene.name} holds detonation products, which fv fluxes with riemann = hllc only "
                                 f"(it advects their volume fraction), got {self.riemann}.")
            if self.levels > 1 or scene.obstacles or scene.dim == 3:
                raise InputError(f"fv runs detonation products on a uniform 1D or 2D grid without bodies for now, and "
                                 f"{scene.name} asks for {'levels > 1' if self.levels > 1 else 'bodies or 3D'}.")
        if self.levels == 1:
            return
        if scene.dim == 3:
            raise InputError(f"levels > 1 refines 1D and 2D scenes for now, and {scene.name} is 3D: use levels = 1.")
        if self.derefine > self.refine:
            raise InputError(f"derefine must not exceed refine ({self.refine:g}), got {self.derefine:g}.")
        if scene.obstacles and scene.geometry != "planar":
            raise InputError(f"levels > 1 runs obstacles in planar scenes only for now, and {scene.name} is "
                             f"{scene.geometry} with {len(scene.obstacles)}: use levels = 1.")
        layout_for(scene.domain, self.dx, self.levels, boundary_kinds(scene), self.block)


def boundary_kinds(scene) -> tuple[str, ...]:
    """The boundary kind of every side of ``scene`` (x_lo, x_hi[, y_lo, y_hi]): an inflow side is ``inflow``."""
    return tuple("inflow" if isinstance(scene.boundaries[s], Inflow) else scene.boundaries[s] for s in scene.sides)


def memory(scene, settings: FVSettings) -> Memory:
    if settings.levels > 1:
        return Memory(elements_in(scene.domain, settings.dx), refined_cell_bytes(scene.dim + 2, scene.dim), "cells",
                      "dx or levels")
    variables = scene.dim + 2 + (3 if scene.detonation is not None else 0)  # (the mixture's three scalars)
    return Memory(elements_in(scene.domain, settings.dx), grid_cell_bytes(variables, scene), "cells")


def refined_cell_bytes(variables: int, dim: int) -> float:
    """Bytes per finest cell of a hierarchy: every level is stored whole
    (the finest its state; the coarser ones, 1/(2^dim − 1) of the finest
    cells or less, their state, the state their step began from and Δt F
    through every face), and one step's arrays for the active blocks with their
    ghosts, assumed to hold a quarter of the finest cells."""
    coarser = 1.0 / (2 ** dim - 1)  # the coarser levels' cells over the finest's, at most
    return 8.0 * variables * (1.0 + (2.0 + dim) * coarser + 0.25 * 15 * 1.6)


METHOD = Method("fv", "gas", FVSettings, memory, "partmesh.gridref.euler.solve:solve",
                geometries=("planar", "axisymmetric", "spherical"), dims=(1, 2, 3), detonations=True)
