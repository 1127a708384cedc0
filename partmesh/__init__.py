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

``import partmesh`` loads only the errors; every other name loads its
module when it is first used (PEP 562, the table ``_LAZY``), so that a
script or ``partmesh --help`` does not pay for xarray, pandas, SciPy and
matplotlib before it needs them.
"""

from partmesh.cases.errors import InputError, SolverFailed, Unsupported
from partmesh.compare.lazy import lazy_names

#: name -> "module:attribute" (or "module", for a module), loaded when first used
_LAZY = {
    "Method": "partmesh.cases.method:Method",
    "Scene": "partmesh.cases.scene:Scene",
    "WaterScene": "partmesh.cases.scene:WaterScene",
    "SchemaError": "partmesh.compare.schema:SchemaError",
    "validate": "partmesh.compare.schema:validate",
    "version": "partmesh.compare.schema:version",
    "read": "partmesh.compare.io:read",
    "write": "partmesh.compare.io:write",
    "registry": "partmesh.cases.registry",
    "scene": "partmesh.cases.registry:get",
    "scenes": "partmesh.cases.registry:names",
    "scene_parameters": "partmesh.cases.registry:defaults",
    "method": "partmesh.cases.registry:method",
    "run": "partmesh.dispatch:run",
    "report": "partmesh.reporting:report",
    "sweep": "partmesh.sweeps:sweep",
    "open_sweep": "partmesh.sweeps:open_sweep",
    "study": "partmesh.blast_study:run_study",
    "study_ladder": "partmesh.blast_study:run_sensitivity",
    "bench": "partmesh.bench",
    "blast_study": "partmesh.blast_study",
    "cluster": "partmesh.cluster",
    "demo": "partmesh.demo",
    "dispatch": "partmesh.dispatch",
    "ensembles": "partmesh.ensembles",
    "reporting": "partmesh.reporting",
    "sweeps": "partmesh.sweeps",
    "warm": "partmesh.warmup:warm",
}


_lazy_getattr, _lazy_dir = lazy_names(__name__, _LAZY, globals())


def __getattr__(name: str):
    """A name of ``_LAZY`` (or ``__version__``), imported on its first use and kept."""
    if name == "__version__":
        globals()[name] = _lazy_getattr("version")()
        return globals()[name]
    return _lazy_getattr(name)


def methods() -> list[str]:
    """Names of the registered methods (entry-point group ``partmesh.methods``)."""
    return sorted(__getattr__("registry").methods())


def __dir__() -> list[str]:
    """The package's names, those not yet loaded among them."""
    return sorted({*_lazy_dir(), "__version__"})


__all__ = [
    "InputError", "Method", "Scene", "SchemaError", "SolverFailed", "Unsupported", "WaterScene",
    "method", "methods", "open_sweep", "read", "report", "run", "scene", "scene_parameters", "scenes",
    "study", "study_ladder", "sweep", "validate", "write", "__version__",
]
