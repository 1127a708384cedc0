"""Equilibrium (Pullin-style) DSMC (SPEC §3.3): particles in free flight,
redrawn from the local equilibrium in every cell after each step.

Modules: :mod:`~particle.dsmc.random` (counter-based random streams, one per
cell and step), :mod:`~particle.dsmc.equilibrate` (the conservative
equilibrium redraw), :mod:`~particle.dsmc.collide` (true VHS /
Larsen–Borgnakke collisions, the non-equilibrium option),
:mod:`~particle.dsmc.move` (free flight, specular plane walls, periodic
wrap, open sides), :mod:`~particle.dsmc.walls` (specular reflection from
the obstacles' convex polygons), :mod:`~particle.dsmc.gas` (equilibrium
particles), :mod:`~particle.dsmc.sample` (cell moments),
:mod:`~particle.dsmc.cells` (the cell sort), :mod:`~particle.dsmc.method`
(the settings and registry entry of method ``dsmc``),
:mod:`~particle.dsmc.solve` (the run).
"""
