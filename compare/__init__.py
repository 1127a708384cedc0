"""Schema, netCDF I/O, exact solutions, metrics and reports.

``compare`` imports none of the other partmesh packages: it is the common
ground that solvers write to and studies read from.
"""

from partmesh.compare.io import read, write
from partmesh.compare.schema import SchemaError, result, validate

__all__ = ["SchemaError", "read", "result", "validate", "write"]
