"""Scenes as plain data: what is simulated, not how.

A :class:`Scene` holds the dimension, domain, gas, initial state, boundaries,
obstacles, probes, the output grid and times, and the default resolution.
Every solver reads the same Scene and writes its fields on the scene's
:class:`OutputGrid`, so results of different methods subtract directly.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from partmesh.cases.checks import check_geometry, check_scene, choice, in_range, positive
from partmesh.cases.errors import InputError
from partmesh.cases.parts import Detonation, Inflow, OutputGrid, Probe, Wall

SIDES = ("x_lo", "x_hi", "y_lo", "y_hi", "z_lo", "z_hi")
BOUNDARY_KINDS = ("reflect", "outflow", "periodic")

__all__ = ["BOUNDARY_KINDS", "Detonation", "Inflow", "OutputGrid", "Precursor", "Probe", "SIDES", "Scene", "Wall",
           "WaterScene"]


class _Scenes:
    """What every scene, gas or water, answers: its sides, its exact
    solution and its parameters."""

    #: the time the initial state holds, and the run that computes it (see :class:`Scene`)
    t_start = 0.0
    precursor = None
    @property
    def sides(self) -> tuple[str, ...]:
        return SIDES[: 2 * self.dim]

    @property
    def periodic(self) -> tuple[bool, ...]:
        """Whether the domain wraps around along x (and y, z)."""
        return tuple(self.boundaries[side] == "periodic" for side in self.sides[::2])

    def exact(self, times=None):
        """The exact solution at ``times`` (default: the output times) as a
        schema Dataset, or ``None`` where the scene has none."""
        if self.exact_solution is None:
            return None
        return self.exact_solution(np.asarray(self.output.times if times is None else times, float))

    def side_area(self, side: str) -> float:
        """The area of ``side`` (one of :attr:`sides`) of a 2D or 3D domain [m²]:
        planar 2D, per metre depth (its length); 3D, the face's; axisymmetric, the whole
        revolved side (a disc or annulus across the axis, a cylinder along it)."""
        i = self.sides.index(side)
        if self.dim == 3:
            (a_lo, a_hi), (b_lo, b_hi) = (extent for k, extent in enumerate(self.domain) if k != i // 2)
            return (a_hi - a_lo) * (b_hi - b_lo)
        if self.geometry != "axisymmetric":
            lo, hi = self.domain[1 - i // 2]
            return hi - lo
        (r_lo, r_hi), (z_lo, z_hi) = self.domain
        return 2.0 * np.pi * (r_lo if i == 0 else r_hi) * (z_hi - z_lo) if i < 2 else np.pi * (r_hi ** 2 - r_lo ** 2)

    def to_dict(self) -> dict:
        """The scene's parameters in JSON-able form (stored in every result)."""
        return {"case": self.name, **self.parameters}


@dataclass(frozen=True)
class Precursor:
    """The run that makes a scene's starting state: ``scene`` run with
    ``method`` and ``settings`` (a dict) to its ``t_end``; ``start(result)``
    turns that run's result into the :class:`Scene` to run (its initial
    state the result's last frame, remapped, and ``t_start`` its time)."""

    scene: "Scene"
    method: str
    settings: dict
    start: Callable


@dataclass(frozen=True)
class Scene(_Scenes):
    """One scene of the toolkit (see SPEC §4).

    ``initial(x, y, dx)`` returns primitive ``(rho, u, v, p)`` arrays at the
    points ``(x, y)`` (``y`` is ``None`` in 1D); ``dx`` is the spacing of the
    points, for scenes that deposit a quantity over a few cells (Sedov). In
    3D it is ``initial(x, y, dx, z)`` and returns ``(rho, u, v, w, p)``.
    ``boundaries`` maps each side of the domain to ``"reflect"``,
    ``"outflow"``, ``"periodic"`` or an :class:`Inflow`.
    ``exact_solution(times)``, where the scene has one, returns a schema
    Dataset on the output grid. ``measure(result)``, where given, returns the
    scene's measured quantities (e.g. a shock angle) as attributes to attach
    to every result. ``tiles`` > 1 says the domain is one period across y of
    a channel that many periods wide, computed once and tiled onto the
    channel by :func:`partmesh.dispatch.run` (:func:`partmesh.cases.tiling.tiled`).
    ``geometry`` is ``"planar"``, ``"axisymmetric"`` (x is the distance r
    from a symmetry axis at x = 0, the ``x_lo`` side, which reflects; in 2D y
    is z along the axis, in 1D the scene is a cylinder's radius) or
    ``"spherical"`` (1D: x is the distance from the centre at x = 0).
    ``t_start`` is the time the initial state holds (0 unless the scene
    starts from a state computed before, see ``precursor``): a run begins
    there, and its output and probe times are absolute.
    ``precursor``, where given, is the run that computes the scene's
    starting state (:class:`Precursor`): :func:`partmesh.dispatch.run` runs
    it first and then the scene its result makes.
    ``detonation``, where given, is a charge of high explosive in the gas
    (:class:`Detonation`); ``initial`` then gives the air's state, and the
    charge fills its ``fraction`` of every cell at rest at the air's pressure.
    """
    name: str
    parameters: dict
    dim: int
    domain: tuple[tuple[float, float], ...]
    gamma: float
    initial: Callable
    boundaries: dict
    output: OutputGrid
    dx: float
    t_end: float
    obstacles: tuple = ()
    probes: tuple[Probe, ...] = ()
    wall: Wall | None = None
    fields: tuple[str, ...] = ("rho", "u", "p", "e")
    exact_solution: Callable | None = None
    measure: Callable | None = None
    description: str = ""
    tiles: int = 1
    geometry: str = "planar"
    t_start: float = 0.0
    precursor: Precursor | None = None
    detonation: Detonation | None = None

    #: what the scene holds; a method runs the scenes of its medium only
    medium = "gas"
    #: the schema's series of the probes
    probe_variable = "p_probe"
    boundary_kinds = BOUNDARY_KINDS

    def __post_init__(self):
        check_scene(self)
        check_geometry(self)
        in_range("gamma", self.gamma, 1.0, 5.0, lo_open=True)



@dataclass(frozen=True)
class WaterScene(_Scenes):
    """A free-surface water scene (SPEC §4.3): still water whose surface is
    at η = 0, over the bed ``bed(x, y)`` (its elevation z [m], negative
    below the still surface: a flat bottom of depth d is ``z = −d``).

    ``initial(x, y)`` returns ``(eta, u, v)`` arrays (``y`` is ``None`` in
    1D): the initial surface elevation and velocity; the depth is
    ``max(0, η − z)``, so land above the surface starts dry.
    ``geometry`` is ``"planar"`` or ``"radial"`` (1D only: ``x`` is the
    radius of an axisymmetric run, side ``x_lo`` at r = 0 the ``axis``).
    ``boundaries`` maps each side to one of :attr:`boundary_kinds`
    (``absorbing``: long waves leave without reflection). ``probes`` are
    wave gauges (the series ``eta_probe``); ``depth`` is the still-water
    depth that sets the scale (long-wave speed sqrt(g d)). ``fields``
    defaults to ``eta``, the depth-averaged velocity (``u``, and ``v`` in
    2D) and the depth ``h``. The rest is as in :class:`Scene`.
    """
    name: str
    parameters: dict
    dim: int
    domain: tuple[tuple[float, float], ...]
    depth: float
    bed: Callable
    initial: Callable
    boundaries: dict
    output: OutputGrid
    dx: float
    t_end: float
    geometry: str = "planar"
    g: float = 9.81
    rho: float = 1000.0
    probes: tuple[Probe, ...] = ()
    fields: tuple[str, ...] | None = None
    exact_solution: Callable | None = None
    measure: Callable | None = None
    description: str = ""

    medium = "water"
    probe_variable = "eta_probe"
    boundary_kinds = ("reflect", "outflow", "absorbing", "periodic", "axis")
    obstacles = ()
    wall = None

    def __post_init__(self):
        if self.fields is None:  # (the velocity's components: u, and v in 2D)
            object.__setattr__(self, "fields", ("eta", "u", "v", "h") if self.dim == 2 else ("eta", "u", "h"))
        check_scene(self)
        positive("depth", self.depth)
        positive("g", self.g)
        choice("geometry", self.geometry, ("planar", "radial"))
        if self.geometry == "radial" and (self.dim != 1 or self.boundaries["x_lo"] != "axis" or self.domain[0][0] != 0.0):
            raise InputError(f"scene {self.name}: a radial scene is 1D over r in [0, R] with the axis at x_lo.")
        if "axis" in [self.boundaries[s] for s in self.sides] and self.geometry != "radial":
            raise InputError(f"scene {self.name}: the boundary kind 'axis' belongs to radial scenes only.")
