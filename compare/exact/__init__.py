"""Exact solutions to compare runs against (SPEC §5).

* :mod:`partmesh.compare.exact.riemann` — exact Riemann solver, vacuum included (Toro 2009, ch. 4)
* :mod:`partmesh.compare.exact.shocks` — normal shock, shock reflection, theta-beta-M,
  Friedlander and Rankine-Hugoniot blast inflow (Anderson; Kinney & Graham)
* :mod:`partmesh.compare.exact.sedov` — Sedov-Taylor point blast (Sedov 1959; Kamm & Timmes 2007)
* :mod:`partmesh.compare.exact.noh` — Noh's implosion (Noh 1987)
* :mod:`partmesh.compare.exact.water` — linear dispersive waves from an initial elevation at rest,
  planar and radial, finite depth (Whitham 1974 §13; Prins 1958)
* :mod:`partmesh.compare.exact.stoker_ritter` — the shallow-water dam break on a wet (Stoker 1957)
  or dry (Ritter 1892) bed
* :mod:`partmesh.compare.exact.detonation` — a planar Chapman–Jouguet detonation from a rigid wall and
  the Taylor wave behind it, for any JWL products (Taylor 1950; Fickett & Davis 1979 §2C)
* :mod:`partmesh.compare.exact.kingery_bulmash` — the blast parameters of a hemispherical TNT surface
  burst against scaled distance (Kingery & Bulmash 1984, Swisdak's 1994 fits): ``kingery_bulmash.blast_parameters``

Functions that describe fields return a Dataset in the partmesh schema with
``method = "exact"``, so an exact answer compares like a run.
"""

from partmesh.compare.exact.noh import noh, noh_profile
from partmesh.compare.exact.riemann import riemann, sample, star_state
from partmesh.compare.exact.sedov import sedov, sedov_alpha, sedov_profile, shock_radius
from partmesh.compare.lazy import lazy_names

#: name -> "module:attribute" (or "module"), loaded when first used (SciPy); the solutions named like
#: their modules load at import, so that importing such a module cannot shadow its function
_LAZY = {
    "kingery_bulmash": "partmesh.compare.exact.kingery_bulmash",
    "TaylorWave": "partmesh.compare.exact.detonation:TaylorWave",
    "taylor_wave": "partmesh.compare.exact.detonation:taylor_wave",
    "planar_detonation": "partmesh.compare.exact.detonation:planar_detonation",
    "BLASTS": "partmesh.compare.exact.shocks:BLASTS",
    "driver_pressure": "partmesh.compare.exact.shocks:driver_pressure",
    "friedlander": "partmesh.compare.exact.shocks:friedlander",
    "max_deflection": "partmesh.compare.exact.shocks:max_deflection",
    "normal_shock": "partmesh.compare.exact.shocks:normal_shock",
    "rankine_hugoniot_inflow": "partmesh.compare.exact.shocks:rankine_hugoniot_inflow",
    "reflected_shock": "partmesh.compare.exact.shocks:reflected_shock",
    "reflection_coefficient": "partmesh.compare.exact.shocks:reflection_coefficient",
    "theta_beta_mach": "partmesh.compare.exact.shocks:theta_beta_mach",
    "DamBreakState": "partmesh.compare.exact.stoker_ritter:DamBreakState",
    "dam_break": "partmesh.compare.exact.stoker_ritter:dam_break",
    "dam_break_profile": "partmesh.compare.exact.stoker_ritter:dam_break_profile",
    "dam_break_state": "partmesh.compare.exact.stoker_ritter:dam_break_state",
    "CRATER_GAUGES": "partmesh.compare.exact.water:CRATER_GAUGES",
    "Crater": "partmesh.compare.exact.water:Crater",
    "Gaussian": "partmesh.compare.exact.water:Gaussian",
    "InitialShape": "partmesh.compare.exact.water:InitialShape",
    "Mound": "partmesh.compare.exact.water:Mound",
    "PRINS_GAUGES": "partmesh.compare.exact.water:PRINS_GAUGES",
    "dispersion": "partmesh.compare.exact.water:dispersion",
    "group_velocity": "partmesh.compare.exact.water:group_velocity",
    "linear_wave_fields": "partmesh.compare.exact.water:linear_wave_fields",
    "linear_waves": "partmesh.compare.exact.water:linear_waves",
    "standing_wave": "partmesh.compare.exact.water:standing_wave",
    "standing_wave_fields": "partmesh.compare.exact.water:standing_wave_fields",
}

__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())

__all__ = [
    "BLASTS",
    "CRATER_GAUGES",
    "PRINS_GAUGES",
    "TaylorWave",
    "Crater",
    "DamBreakState",
    "Gaussian",
    "InitialShape",
    "Mound",
    "dam_break",
    "dam_break_profile",
    "dam_break_state",
    "dispersion",
    "driver_pressure",
    "friedlander",
    "group_velocity",
    "kingery_bulmash",
    "linear_wave_fields",
    "linear_waves",
    "max_deflection",
    "noh",
    "noh_profile",
    "normal_shock",
    "planar_detonation",
    "rankine_hugoniot_inflow",
    "reflected_shock",
    "reflection_coefficient",
    "riemann",
    "sample",
    "sedov",
    "sedov_alpha",
    "sedov_profile",
    "shock_radius",
    "standing_wave",
    "standing_wave_fields",
    "star_state",
    "taylor_wave",
    "theta_beta_mach",
]
