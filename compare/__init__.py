"""Schema, netCDF I/O, exact solutions, metrics and reports.

``compare`` imports none of the other partmesh packages: it is the common
ground that solvers write to and studies read from.

The names below load :mod:`~partmesh.compare.schema` and
:mod:`~partmesh.compare.io` (and with them xarray) when first used
(PEP 562), so that importing the package, or :mod:`partmesh.compare.checks`
from it, stays light.
"""

import importlib

#: name -> "module:attribute", loaded when first used
_LAZY = {
    "SchemaError": "partmesh.compare.schema:SchemaError",
    "result": "partmesh.compare.schema:result",
    "validate": "partmesh.compare.schema:validate",
    "read": "partmesh.compare.io:read",
    "write": "partmesh.compare.io:write",
}


def __getattr__(name: str):
    """A name of ``_LAZY``, imported on its first use and kept."""
    if name not in _LAZY:
        raise AttributeError(f"module 'partmesh.compare' has no attribute {name!r}")
    module, _, attribute = _LAZY[name].partition(":")
    value = getattr(importlib.import_module(module), attribute)
    globals()[name] = value  # (looked up once)
    return value


def __dir__() -> list[str]:
    """The package's names, those not yet loaded among them."""
    return sorted({*globals(), *_LAZY})


__all__ = ["SchemaError", "read", "result", "validate", "write"]
