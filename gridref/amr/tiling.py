"""A batch of block windows laid side by side as one array, so that the
uniform grid's stencil kernels advance every block at once.

``n`` windows of ``h`` cells a side (a block and its ghost layers) become
one array of ``R × C`` windows (2D; one row of windows in 1D). A stencil
kernel run over it computes, near the seams between two windows, values
that mix both: they land in each window's ghost layers only, which a
window's own cells never read through a stencil no wider than its ghosts,
and which :func:`windowed` leaves out. Batched this way the kernels run at
the uniform grid's speed per cell; batched with ``jax.vmap`` over small
windows, XLA on the CPU ran them three to nine times slower (measured with
a MUSCL–Hancock step on 16² and 32² blocks).
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp


def rows_for(n: int) -> int:
    """Rows of windows for ``n`` windows: the largest divisor of ``n`` up to
    half its square root (a wide array, fastest in the measurements)."""
    limit = max(1, int(math.isqrt(n) // 2))
    return max(d for d in range(1, limit + 1) if n % d == 0)


def tiled(a, rows: int):
    """Windows ``a`` (n, h[, h]) side by side: (rows·h, n/rows·h) in 2D, (n·h,) in 1D."""
    if a.ndim == 2:
        return a.reshape(-1)
    n, h, w = a.shape
    return a.reshape(rows, n // rows, h, w).transpose(0, 2, 1, 3).reshape(rows * h, (n // rows) * w)


def windowed(a, rows: int, n: int, h: int, sizes: tuple[int, ...]):
    """The inverse of :func:`tiled` for an array computed from a tiled one and
    cut short at the end (a stencil's output, starting ``k`` cells into the
    tiled array): each window's first ``sizes`` cells (per axis, laid out
    ``([y,] x)``) counted from ``k`` into that window, as an array ``(n, *sizes)``."""
    if a.ndim == 1:
        a = jnp.pad(a, (0, n * h - a.shape[0]))
        return a.reshape(n, h)[:, : sizes[0]]
    cols = n // rows
    a = jnp.pad(a, ((0, rows * h - a.shape[0]), (0, cols * h - a.shape[1])))
    a = a.reshape(rows, h, cols, h)[:, : sizes[0], :, : sizes[1]]
    return a.transpose(0, 2, 1, 3).reshape(n, *sizes)


#: cells of the blocks advanced together (tiled side by side): enough for the kernels to run near a whole grid's
#: speed, few enough that the last chunk of a level, which the level's blocks fill only in part, wastes little.
#: XLA on the CPU splits an operation over the cores only where it is large: a chain of stencil stages on tiled
#: windows of 12 800 cells (32 blocks of 16² with their ghosts) ran as fast on one core as on two, on 25 600 cells
#: 1.6 times faster on two (measured on this project's 2-core machine). 64 blocks of 16² (16 of 32²): the refined
#: 2D Sedov bench (512², three levels) 6.1 → 6.6e6 updated cells/s, four runs each, alternating in one process
CHUNK_CELLS = 16384


def chunk_for(n: int, block_cells: int) -> int:
    """The blocks of a chunk for a list of ``n`` blocks of ``block_cells``
    cells: the largest divisor of ``n`` whose blocks hold at most
    :data:`CHUNK_CELLS` cells (one block at least)."""
    most = max(1, CHUNK_CELLS // block_cells)
    return max(d for d in range(1, min(n, most) + 1) if n % d == 0)


def over_chunks(ids, count, body, carry, block_cells: int):
    """``carry`` passed through ``body(chunk, carry)`` for every chunk of
    :func:`chunk_for` ids of the list ``ids`` (blocks of ``block_cells``
    cells) that holds any of its first ``count`` (a traced number): a loop
    whose trip count follows the blocks listed, not the list's capacity.
    The ids past ``count`` in the last chunk are the list's padding (one
    past the last block), which gathers clamp and scatters drop."""
    K = chunk_for(ids.shape[0], block_cells)

    def step(c, carry):
        return body(jax.lax.dynamic_slice_in_dim(ids, c * K, K), carry)

    return jax.lax.fori_loop(0, (count + K - 1) // K, step, carry)
