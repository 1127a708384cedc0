"""Hybrid finite-volume – SPH (method ``hybrid``, SPEC §3.6): a coarse
MUSCL–Hancock grid everywhere, SPH particles only in the cells flagged by a
gradient threshold, coupled conservatively. Its settings and registry
entry are in :mod:`partmesh.hybrid.method`, the run in :mod:`partmesh.hybrid.solve`."""
