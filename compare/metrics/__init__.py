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

from partmesh.compare.metrics.conservation import conservation_drift
from partmesh.compare.metrics.field_errors import NORMS, errors, field_error
from partmesh.compare.metrics.oblique_shock import oblique_shock_angle
from partmesh.compare.metrics.probe_series import (
    arrival_time,
    first_crest,
    peak,
    plateau,
    positive_phase,
    running_peak,
    shock_fitted_peak,
)
from partmesh.compare.metrics.schlieren import schlieren
from partmesh.compare.metrics.shock_position import ring_profile, shock_position, shock_radius
from partmesh.compare.metrics.units import MEASURED_UNITS, measured_unit

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
