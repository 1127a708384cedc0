"""Particle solvers (numba): gas SPH (``partmesh.particle.sph``, method ``sph``),
water SPH (``partmesh.particle.wcsph``, method ``wcsph``) and equilibrium DSMC
(``partmesh.particle.dsmc``, method ``dsmc``). Each registers its
:class:`~partmesh.cases.method.Method` under the ``partmesh.methods`` entry-point
group; :mod:`partmesh.particle.march` is their time loop.

Importing the package sets ``OMP_WAIT_POLICY=PASSIVE`` unless the user set it
(see :data:`partmesh.particle.threads.WAIT_POLICY`), before numba's OpenMP
threads start: their default spin-wait turns a step of two threads into a
hundredfold longer one when another process holds a core."""

from partmesh.particle.threads import passive_waits

passive_waits()
