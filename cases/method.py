"""The contract every method keeps (SPEC §1), in the style of PyClaw's
``Solver`` and PySPH's ``Scheme``: a :class:`Method` declares its name, the
medium it runs, whether it takes a ``seed``, its frozen settings dataclass
(:mod:`partmesh.cases.settings`), the memory a run needs and where its solver lives.

A package registers a method by naming its ``Method`` in the entry-point
group ``partmesh.methods``; :func:`partmesh.dispatch.run` finds it there. A run
checks the settings and the memory first and imports the solver module
only then (for a grid method, JAX), so bad input is refused in a second
or two, before any compilation.

The solver, ``solve(scene, settings) -> Dataset``, supplies the step
protocol and hands it to the one time loop, :func:`partmesh.cases.march.march`:

- its record, a :class:`partmesh.cases.history.RunRecord` subclass: the fields of a
  state on the scene's output grid (``fields``), its conserved totals
  (``totals``), the scheme and attributes of the result (``output``);
- the initial state, its time and stable step (a resumed run takes them
  from :class:`partmesh.cases.checkpoint.Checkpoint`);
- ``advance``: a stretch of steps with its probe values and side forces
  (:class:`partmesh.cases.march.Stretch`) — compiled on the device for a grid
  method, one host step for the others (:class:`partmesh.cases.march.single_steps`);
- ``saved_state``: what a checkpoint keeps of a state, and ``diagnose``:
  the one sentence a failed step ends with.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable

from partmesh.cases.memory import check_fits
from partmesh.cases.settings import Settings


@dataclass(frozen=True)
class Memory:
    """What a run allocates: ``elements`` (cells or particles) of
    ``bytes_each`` bytes, what they are called, and the setting to raise to
    make them fewer."""

    elements: float
    bytes_each: float
    what: str
    setting: str = "dx"


@dataclass(frozen=True)
class Method:
    """One method: ``name``; the ``medium`` of the scenes it runs ("gas" or
    "water"); whether it ``takes_seed`` (a stochastic method, which
    ensembles can average); its ``settings`` class; ``memory(scene,
    settings) -> Memory``; ``solver``, the ``"module:function"`` of its
    ``solve(scene, settings)``; and the ``geometries`` of the gas scenes it
    runs (:data:`partmesh.cases.checks.GAS_GEOMETRIES`); whether it runs
    ``detonations`` (charges of detonation products, :class:`~partmesh.cases.parts.Detonation`)."""

    name: str
    medium: str
    settings: type[Settings]
    memory: Callable
    solver: str
    takes_seed: bool = False
    geometries: tuple[str, ...] = ("planar",)
    dims: tuple[int, ...] = (1, 2)
    detonations: bool = False

    def refusal(self, scene) -> str | None:
        """Why this method cannot run ``scene`` (one sentence), or None."""
        if scene.medium != self.medium:
            return f"method {self.name} runs {self.medium} scenes, and {scene.name} is a {scene.medium} scene."
        if scene.medium == "gas" and scene.geometry not in self.geometries:
            return (f"method {self.name} runs {' and '.join(self.geometries)} scenes, and {scene.name} is "
                    f"{scene.geometry}.")
        if scene.dim not in self.dims:
            return (f"method {self.name} runs {' and '.join(f'{d}D' for d in self.dims)} scenes, and {scene.name} "
                    f"is {scene.dim}D.")
        if getattr(scene, "detonation", None) is not None and not self.detonations:
            return (f"method {self.name} models an ideal gas only, and {scene.name} holds a charge of JWL detonation "
                    "products: run it with method fv or sph, or (a surface burst) with charge=balloon.")
        return None

    def checked(self, scene, given: dict) -> Settings:
        """The settings ``given`` (values or command-line text), checked for a
        run of ``scene``, and the run checked to fit in memory."""
        settings = self.settings.checked(scene, given)
        need = self.memory(scene, settings)
        check_fits(self.name, need.elements, need.bytes_each, need.what, need.setting)
        return settings

    def solve(self, scene, settings: Settings):
        """Run ``scene`` with checked ``settings``; returns the schema Dataset."""
        module, function = self.solver.split(":")
        return getattr(importlib.import_module(module), function)(scene, settings)
