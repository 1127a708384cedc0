"""Finite-volume Euler solver: unsplit MUSCL–Hancock with swappable Riemann
solvers and limiters, conservative cut-cell immersed boundaries (SPEC §3.4)."""

from gridref.euler.solve import solve

__all__ = ["solve"]
