"""Compressible gas SPH (method ``sph``, SPEC §3.1): summation density with
adaptive smoothing length and grad-h terms, variational momentum and energy
equations, Cullen–Dehnen viscosity, artificial conduction, predictor–corrector
leapfrog, mirror-particle walls."""

from particle.sph.solve import solve

__all__ = ["solve"]
