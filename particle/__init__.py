"""Particle solvers (numba): gas SPH (``particle.sph``, method ``sph``),
water SPH (``particle.wcsph``, method ``wcsph``) and equilibrium DSMC
(``particle.dsmc``, method ``dsmc``). Each registers its
:class:`~cases.method.Method` under the ``partmesh.methods`` entry-point
group; :mod:`particle.march` is their time loop."""
