"""Particle solvers (numba): gas SPH (``particle.sph``, method ``sph``);
water SPH and equilibrium DSMC to come. Each registers itself under the
``partmesh.methods`` entry-point group."""
