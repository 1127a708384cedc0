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

:func:`staged` wraps a kernel in ``lax.cond(gate, kernel, nan)``, whose
other branch fills the kernel's outputs with NaN (False, the most negative
integer): ``gate`` is a traced scalar that is True wherever the step
means anything (a finite time step; the compiler cannot drop the
conditional), and the program holds the kernel once, not twice (half the
compile time of two copies of it). On other backends the kernel is
returned as it is: there, fusing is the compiler's business, and a
conditional costs a synchronisation.
"""

from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp


def staged(kernel: Callable, gate) -> Callable:
    """``kernel`` (a function of arrays and pytrees of arrays) as a stage of
    its own inside a compiled program on the CPU: ``staged(kernel,
    gate)(*args) == kernel(*args)`` where the traced boolean scalar ``gate``
    is True; where it is False, every output is NaN (False, the most
    negative integer)."""
    if jax.default_backend() != "cpu":
        return kernel

    def stage(*args):
        return jax.lax.cond(gate, lambda a: kernel(*a), lambda a: _unset(jax.eval_shape(kernel, *a)), args)

    return stage


def _unset(shapes):
    """Arrays of ``shapes`` (a pytree of shape–dtype structs) holding NaN,
    False or the most negative integer."""
    def filled(s):
        if jnp.issubdtype(s.dtype, jnp.floating):
            value = jnp.nan
        elif jnp.issubdtype(s.dtype, jnp.integer):
            value = jnp.iinfo(s.dtype).min
        else:
            value = False
        return jnp.full(s.shape, value, s.dtype)
    return jax.tree_util.tree_map(filled, shapes)
