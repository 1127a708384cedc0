"""Scenes (geometry, initial and boundary conditions, probes, output grid),
the method runner and the command line.

``cases.get(name, **overrides)`` returns a scene; ``cases.names()`` lists
them; ``cases.run(scene, method, ...)`` runs one with any registered method.
"""

from cases.errors import InputError, SolverFailed
from cases.registry import defaults, get, names
from cases.run import methods, run
from cases.scene import Inflow, OutputGrid, Probe, Scene, Wall

__all__ = [
    "InputError", "Inflow", "OutputGrid", "Probe", "Scene", "SolverFailed", "Wall",
    "defaults", "get", "methods", "names", "run",
]
