"""Scenes (geometry, initial and boundary conditions, probes, output grid)
and the run machinery every method shares: the run record and its history,
the one time loop (:mod:`partmesh.cases.march`), checkpoints, the method
contract (:mod:`partmesh.cases.method`) and its settings.

Scenes are found by name through :mod:`partmesh.cases.registry`; users reach
them as :func:`partmesh.scene` and :func:`partmesh.scenes`.
"""
