"""Weakly compressible water SPH (method ``wcsph``, SPEC §3.2): a planar
water scene as a vertical (x, z) slice, Tait equation of state, continuity
with density diffusion, Monaghan viscosity, gravity, quintic Wendland
kernel, velocity Verlet stepping, mirror-particle walls and a damping zone.
Its settings and registry entry are in :mod:`partmesh.particle.wcsph.method`, the
run in :mod:`partmesh.particle.wcsph.solve`."""
