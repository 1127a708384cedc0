"""Method ``swe``, the shallow-water model: unsplit MUSCL–Hancock with
hydrostatic reconstruction at the faces and HLLC fluxes, wet/dry fronts;
1D, 2D and 1D-radial (SPEC §3.5). Its settings and registry entry are in
:mod:`partmesh.gridref.swe.method`, the step in :mod:`partmesh.gridref.swe.step`, the run in
:mod:`partmesh.gridref.swe.solve`."""
