"""Hybrid finite-volume – SPH (method ``hybrid``, SPEC §3.6): a coarse
MUSCL–Hancock grid everywhere, SPH particles only in the cells flagged by a
gradient threshold, coupled conservatively."""

from hybrid.solve import solve

__all__ = ["solve"]
