"""Particle solvers (numba): gas SPH (``partmesh.particle.sph``, method ``sph``),
water SPH (``partmesh.particle.wcsph``, method ``wcsph``) and equilibrium DSMC
(``partmesh.particle.dsmc``, method ``dsmc``). Each registers its
:class:`~partmesh.cases.method.Method` under the ``partmesh.methods`` entry-point
group; :mod:`partmesh.particle.march` is their time loop."""
