"""The two ways a run stops early: bad input, or a solver that went unstable."""

from __future__ import annotations

from partmesh.compare.checks import InputError

__all__ = ["InputError", "SolverFailed", "Unsupported"]


class Unsupported(InputError):
    """A method that cannot run a scene (DSMC on water, say); the message
    says what the method lacks."""


class SolverFailed(RuntimeError):
    """A run that went unstable. The message says when, where and which
    quantity; ``partial`` holds the result computed up to then, marked
    ``status = "failed"``."""

    def __init__(self, message: str, partial=None):
        super().__init__(message)
        self.partial = partial
