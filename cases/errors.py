"""The two ways a run stops early: bad input, or a solver that went unstable."""

from __future__ import annotations


class InputError(ValueError):
    """A parameter outside its allowed range; the message is one sentence
    naming the parameter and the allowed range (SPEC §9)."""


class SolverFailed(RuntimeError):
    """A run that went unstable. The message says when, where and which
    quantity; ``partial`` holds the result computed up to then, marked
    ``status = "failed"``."""

    def __init__(self, message: str, partial=None):
        super().__init__(message)
        self.partial = partial
