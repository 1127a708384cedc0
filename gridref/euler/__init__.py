"""Method ``fv``, the finite-volume Euler solver: unsplit MUSCL–Hancock with
swappable Riemann solvers and limiters, conservative cut-cell immersed
boundaries (SPEC §3.4). Its settings and registry entry are in
:mod:`partmesh.gridref.euler.method`, the run in :mod:`partmesh.gridref.euler.solve`."""
