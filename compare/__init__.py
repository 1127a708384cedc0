"""Schema, netCDF I/O, exact solutions, metrics and reports.

``compare`` imports none of the other partmesh packages: it is the common
ground that solvers write to and studies read from.

The names below load :mod:`~partmesh.compare.schema` and
:mod:`~partmesh.compare.io` (and with them xarray) when first used
(PEP 562), so that importing the package, or :mod:`partmesh.compare.checks`
from it, stays light.
"""

from partmesh.compare.lazy import lazy_names

#: name -> "module:attribute", loaded when first used
_LAZY = {
    "SchemaError": "partmesh.compare.schema:SchemaError",
    "result": "partmesh.compare.schema:result",
    "validate": "partmesh.compare.schema:validate",
    "read": "partmesh.compare.io:read",
    "write": "partmesh.compare.io:write",
}


__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = ["SchemaError", "read", "result", "validate", "write"]
