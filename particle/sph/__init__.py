"""Compressible gas SPH (method ``sph``, SPEC §3.1): summation density with
adaptive smoothing length and grad-h terms, variational momentum and energy
equations, Cullen–Dehnen viscosity, artificial conduction, predictor–corrector
leapfrog, mirror-particle walls. Its settings and registry entry are in
:mod:`partmesh.particle.sph.method`, the run in :mod:`partmesh.particle.sph.solve`."""
