"""Method ``swe``, the shallow-water model: MUSCL and hydrostatic
reconstruction, HLLC fluxes, SSP-RK2, wet/dry fronts; 1D, 2D and 1D-radial
(SPEC §3.5). Its settings and registry entry are in
:mod:`gridref.swe.method`, the run in :mod:`gridref.swe.solve`."""
