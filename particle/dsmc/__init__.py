"""Equilibrium (Pullin-style) DSMC (SPEC §3.3): particles in free flight,
redrawn from the local equilibrium in every cell after each step.

Modules: :mod:`~particle.dsmc.random` (counter-based random streams, one per
cell and step), :mod:`~particle.dsmc.equilibrate` (the conservative
equilibrium redraw).
"""
