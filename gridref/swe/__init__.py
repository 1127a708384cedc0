"""Shallow-water model: MUSCL and hydrostatic reconstruction, HLLC fluxes,
SSP-RK2, wet/dry fronts; 1D, 2D and 1D-radial (SPEC §3.5)."""

from gridref.swe.solve import solve

#: the scenes this method runs (cases.run refuses the others)
solve.medium = "water"

__all__ = ["solve"]
