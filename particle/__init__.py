"""Particle solvers (numba): gas SPH, water SPH and equilibrium DSMC.

The solvers register themselves under the ``partmesh.methods`` entry-point
group as they land; none is registered yet.
"""
