"""Method ``sph``: its settings and its entry in the method registry
(:mod:`partmesh.cases.method`); the solver is :mod:`partmesh.particle.sph.solve`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from partmesh.cases.errors import InputError
from partmesh.cases.memory import elements_in, particle_bytes
from partmesh.cases.method import Memory, Method
from partmesh.cases.scene import Inflow
from partmesh.cases.settings import Settings, one_of, optional_path, setting, within
from partmesh.particle.kernels import KERNELS, least_eta

#: how the initial particles are laid out: equal masses (spacing dx in the densest gas), or the
#: lattice of spacing dx with masses ρ dx^d (for density contrasts equal masses cannot take, and the
#: ring masses of an axisymmetric scene)
MASSES = ("equal", "lattice")


def has_inlet(scene) -> bool:
    """Whether a side of ``scene`` lets gas in."""
    return any(isinstance(scene.boundaries[side], Inflow) for side in scene.sides)


@dataclass(frozen=True)
class SPHScheme(Settings):
    """The settings of the grad-h SPH scheme (Price 2012): ``kernel``,
    ``eta`` the support radius in units of the local spacing (H = η
    (m/ρ)^(1/d); η = 4 gives H = 4Δx), ``alpha_max``/``alpha_min`` the
    bounds of the Cullen–Dehnen viscosity, ``alpha_u`` the ceiling of the
    conduction coefficient's switch."""

    kernel: str = setting("wendland_c6", one_of(KERNELS), "SPH kernel")
    eta: float = setting(4.0, within(1.0, 8.0),
                         "support radius in local spacings, in [1, 8] and above the kernel's least_eta")
    alpha_max: float = setting(2.5, within(0.0, 10.0), "ceiling of the viscosity switch, in [0, 10]")
    alpha_min: float = setting(0.0, within(0.0, 10.0), "floor of the viscosity switch, in [0, 10]")
    alpha_u: float = setting(1.0, within(0.0, 10.0), "ceiling of the conduction switch, in [0, 10]")

    def check_together(self, scene) -> None:
        super().check_together(scene)
        least = least_eta(self.kernel, scene.dim)
        if not self.eta > least:
            raise InputError(f"eta must exceed {least:.4g} with the {self.kernel} kernel in {scene.dim}D, where a "
                             f"particle's own weight outgrows the density its support asks for and the density has "
                             f"no solution; got {self.eta:g}.")


@dataclass(frozen=True)
class SPHSettings(SPHScheme):
    """Settings of compressible SPH: ``dx`` the initial particle spacing in
    the densest gas (``masses="equal"``) or everywhere (``masses="lattice"``:
    the square lattice, masses ρ dx^d), ``cfl`` the step's Courant number
    (Δt = C min h/v_sig), the scheme's settings (:class:`SPHScheme`), and
    ``particles``, a file to write the last state's particles to (SPEC §2).
    ``masses`` left None is ``"equal"`` in a planar 1D or 2D scene and
    ``"lattice"`` in an axisymmetric one, where ring masses on a lattice are
    the only placement, and in 3D, where the cubic lattice is."""

    method: ClassVar[str] = "sph"

    cfl: float = setting(0.25, within(0.0, 1.0, lo_open=True), "Courant number in (0, 1]")
    masses: str | None = setting(None, one_of(MASSES), "initial particle masses (None: equal, lattice in r-z and 3D)")
    particles: str | None = setting(None, optional_path, "file for the particles of the last state")

    def scene_defaults(self, scene) -> dict:
        lattice = scene.geometry == "axisymmetric" or scene.detonation is not None or scene.dim == 3
        return {**super().scene_defaults(scene),
                "masses": ("lattice" if lattice else "equal") if self.masses is None else self.masses}

    def check_together(self, scene) -> None:
        super().check_together(scene)
        if self.masses == "equal" and scene.geometry == "axisymmetric":
            raise InputError(f"masses='equal' runs planar 1D and 2D scenes; {scene.name} is axisymmetric, where sph "
                             "places ring masses on the lattice (masses='lattice').")
        if self.masses == "equal" and scene.dim == 3:
            raise InputError(f"masses='equal' runs 1D and 2D scenes; {scene.name} is 3D, where sph places the cubic "
                             "lattice (masses='lattice').")
        if self.masses == "equal" and scene.detonation is not None:
            raise InputError(f"masses='equal' runs scenes of one gas; {scene.name} holds detonation products, which "
                             "sph places on the lattice (masses='lattice').")
        if self.masses == "lattice" and has_inlet(scene):
            raise InputError(f"masses='lattice' runs scenes without an inflow side; {scene.name} has one.")


def memory(scene, settings: SPHSettings) -> Memory:
    return Memory(elements_in(scene.domain, settings.dx), particle_bytes(scene.dim, 1.25 * settings.eta),
                  "particles")


METHOD = Method("sph", "gas", SPHSettings, memory, "partmesh.particle.sph.solve:solve",
                geometries=("planar", "axisymmetric"), dims=(1, 2, 3), detonations=True)
