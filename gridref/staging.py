"""Kernel boundaries inside one compiled program.

A grid step is a pipeline of stencil kernels (ghost cells, slopes,
predictor, face fluxes, update), and every kernel reads its input at
shifted positions. Compiled as one program, XLA:CPU fuses each producer
into every one of its consumers and recomputes it there: the slopes and the
predictor are evaluated again inside each flux, and a MUSCL–Hancock step of
256² cells takes 380 ms instead of 13 ms (measured on this project's
machine). ``jax.lax.optimization_barrier`` does not prevent it on the CPU
(the barrier is removed before fusion runs). A conditional does: its
branches are computations of their own, which fusion does not cross, so a
value computed inside one is materialised once.

:func:`staged` wraps a kernel in ``lax.cond(gate, kernel, kernel)``, whose
two branches are the same function: the value never depends on ``gate``
(any traced scalar, so the compiler cannot drop the conditional). On other
backends the kernel is returned as it is: there, fusing is the compiler's
business, and a conditional costs a synchronisation.
"""

from __future__ import annotations

from typing import Callable

import jax


def staged(kernel: Callable, gate) -> Callable:
    """``kernel`` (a function of arrays and pytrees of arrays) as a stage of
    its own inside a compiled program on the CPU: ``staged(kernel,
    gate)(*args) == kernel(*args)`` for any boolean scalar ``gate``."""
    if jax.default_backend() != "cpu":
        return kernel

    def stage(*args):
        return jax.lax.cond(gate, lambda a: kernel(*a), lambda a: kernel(*a), args)

    return stage
