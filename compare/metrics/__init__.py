"""Scalar measures of a result: field errors, shock positions, probe-series
metrics, oblique-shock angles and conservation drift (SPEC §5).

Every function works on the schema's objects (:mod:`partmesh.compare.schema`):
fields are :class:`xarray.DataArray` on ``([y,] x)`` (select a ``time``
first), probe series are 1D DataArrays on ``t_probe`` (select a ``probe``
first, e.g. ``ds.p_probe.sel(probe="w")``). NaN marks cells inside solids or
without support and is left out everywhere.

The measures live in modules named after them; this package gathers
their public names.
"""

from partmesh.compare.lazy import lazy_names
from partmesh.compare.metrics.conservation import conservation_drift
from partmesh.compare.metrics.field_errors import NORMS, errors, field_error
from partmesh.compare.metrics.oblique_shock import oblique_shock_angle
from partmesh.compare.metrics.schlieren import schlieren
from partmesh.compare.metrics.shock_position import ring_profile, shock_position, shock_radius
from partmesh.compare.metrics.units import MEASURED_UNITS, measured_unit

#: name -> "module:attribute", loaded when first used (SciPy)
_LAZY = {
    "arrival_time": "partmesh.compare.metrics.probe_series:arrival_time",
    "first_crest": "partmesh.compare.metrics.probe_series:first_crest",
    "peak": "partmesh.compare.metrics.probe_series:peak",
    "plateau": "partmesh.compare.metrics.probe_series:plateau",
    "positive_phase": "partmesh.compare.metrics.probe_series:positive_phase",
    "running_peak": "partmesh.compare.metrics.probe_series:running_peak",
    "shock_fitted_peak": "partmesh.compare.metrics.probe_series:shock_fitted_peak",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "MEASURED_UNITS",
    "NORMS",
    "arrival_time",
    "conservation_drift",
    "errors",
    "field_error",
    "first_crest",
    "measured_unit",
    "oblique_shock_angle",
    "peak",
    "plateau",
    "positive_phase",
    "ring_profile",
    "running_peak",
    "schlieren",
    "shock_fitted_peak",
    "shock_position",
    "shock_radius",
]
