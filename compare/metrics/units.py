"""The units of the scalar quantities the scenes measure (attached to a
result beside its measured values)."""

from __future__ import annotations

#: units of the scalar quantities scenes measure with this module (``partmesh.dispatch`` attaches them to a result)
MEASURED_UNITS = {
    "wall_peak_pressure_raw": "Pa", "wall_peak_pressure_fitted": "Pa", "wall_arrival_time": "s",
    "wall_impulse_final": "N s m-1", "wall_force_peak_raw": "N m-1",
    "wall_force_peak_fitted": "N m-1", "wall_force_peak_mean": "N m-1", "reflection_coefficient": "1",
    "shock_angle_deg": "degree", "shock_radius": "m", "first_crest_height": "m", "first_crest_time": "s",
    "first_crest_arrival": "s",
}


def measured_unit(name: str) -> str | None:
    """The unit of the measured quantity ``name``: from :data:`MEASURED_UNITS`,
    by its name or, for per-probe quantities (``first_crest_height_x4.57``),
    by the name they extend."""
    if name in MEASURED_UNITS:
        return MEASURED_UNITS[name]
    stems = [key for key in MEASURED_UNITS if name.startswith(key + "_")]
    return MEASURED_UNITS[max(stems, key=len)] if stems else None
