"""Equilibrium (Pullin-style) DSMC (SPEC §3.3): particles in free flight,
redrawn from the local equilibrium in every cell after each step.

Modules: :mod:`~partmesh.particle.dsmc.random` (counter-based random streams, one per
cell and step), :mod:`~partmesh.particle.dsmc.equilibrate` (the conservative
equilibrium redraw), :mod:`~partmesh.particle.dsmc.collide` (true VHS /
Larsen–Borgnakke collisions, the non-equilibrium option),
:mod:`~partmesh.particle.dsmc.move` (free flight, specular plane walls, periodic
wrap, open sides), :mod:`~partmesh.particle.dsmc.walls` (specular reflection from
the obstacles' convex polygons), :mod:`~partmesh.particle.dsmc.gas` (equilibrium
particles), :mod:`~partmesh.particle.dsmc.sample` (cell moments),
:mod:`~partmesh.particle.dsmc.cells` (the cell sort), :mod:`~partmesh.particle.dsmc.method`
(the settings and registry entry of method ``dsmc``),
:mod:`~partmesh.particle.dsmc.reservoirs` (the gas beyond open sides),
:mod:`~partmesh.particle.dsmc.far_field` (an outflow's far-field state),
:mod:`~partmesh.particle.dsmc.axisymmetric` (r–z flight and the resampling redraw),
:mod:`~partmesh.particle.dsmc.solve` (the run).
"""
