"""partmesh: blast and water-wave scenes run with particle and mesh
methods, written in one xarray schema and compared field by field.

The one place users import from::

    import partmesh as pm

    ds = pm.run("sod", "fv", dx=2.5e-3)            # a schema Dataset
    pm.report([ds], reference="exact", output="sod-report")
    pm.scenes(), pm.methods()                      # what there is
    pm.scene("blast_array", shape="square")        # a scene, every parameter checked

Below it, in layers that import one way only:
:mod:`partmesh.compare` (schema, I/O, exact solutions, metrics, reports)
← :mod:`partmesh.cases` (scenes and the run machinery every method shares)
← :mod:`partmesh.gridref`, :mod:`partmesh.particle` (the methods)
← :mod:`partmesh.hybrid` ← ``partmesh`` (dispatch, ensembles, sweeps,
studies, demo, bench, the command line).
"""

from partmesh.blast_study import run_sensitivity as study_ladder
from partmesh.blast_study import run_study as study
from partmesh.cases import registry
from partmesh.cases.errors import InputError, SolverFailed, Unsupported
from partmesh.cases.method import Method
from partmesh.cases.registry import defaults as scene_parameters
from partmesh.cases.registry import get as scene
from partmesh.cases.registry import method
from partmesh.cases.registry import names as scenes
from partmesh.cases.scene import Scene, WaterScene
from partmesh.compare.io import read, write
from partmesh.compare.schema import SchemaError, validate, version
from partmesh.dispatch import run
from partmesh.reporting import report
from partmesh.sweeps import open_sweep, sweep

__version__ = version()


def methods() -> list[str]:
    """Names of the registered methods (entry-point group ``partmesh.methods``)."""
    return sorted(registry.methods())


__all__ = [
    "InputError", "Method", "Scene", "SchemaError", "SolverFailed", "Unsupported", "WaterScene",
    "method", "methods", "open_sweep", "read", "report", "run", "scene", "scene_parameters", "scenes",
    "study", "study_ladder", "sweep", "validate", "write", "__version__",
]
