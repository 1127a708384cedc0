"""Which blocks of each level are active: boolean maps of a level's blocks
laid out ``([by,] bx)``, and the lists of block ids the compiled update
loops over.

Proper nesting (Berger & Colella 1989): a level's blocks, dilated by two
of their own blocks, lie inside the next coarser level's active blocks, so
that every ghost cell a fine block or its halo needs from the coarser
level is read from cells that level advances.
"""

from __future__ import annotations

import jax.numpy as jnp

from partmesh.gridref.amr.transfer import repeated


def dilated(active, periodic, radius: int = 1):
    """``active`` grown by ``radius`` blocks along every axis, diagonals
    included: wrapped around along ``periodic`` axes (x first), cut at the
    other sides."""
    ndim = active.ndim
    for _ in range(radius):
        for d in range(ndim):
            axis = ndim - 1 - d
            if periodic[d]:
                grown = jnp.roll(active, 1, axis) | jnp.roll(active, -1, axis)
            else:
                pad = [(0, 0)] * ndim
                pad[axis] = (1, 1)
                p = jnp.pad(active, pad)
                n = active.shape[axis]
                grown = jnp.take(p, jnp.arange(0, n), axis=axis) | jnp.take(p, jnp.arange(2, n + 2), axis=axis)
            active = active | grown
    return active


def parents(active):
    """The blocks of the coarser level with at least one active child."""
    shape = []
    for n in active.shape:
        shape += [n // 2, 2]
    return jnp.any(active.reshape(shape), axis=tuple(range(1, 2 * active.ndim, 2)))


def children(active):
    """The blocks of the finer level whose parent is active."""
    return repeated(active, 2)


def listed(active, capacity: int):
    """``(ids, count)``: the flat ids of the active blocks in increasing
    order, padded to ``capacity`` with the id one past the last block (which
    a scatter drops), and how many there are (may exceed ``capacity``: the
    list is then cut and the caller must grow it)."""
    flat = active.ravel()
    ids = jnp.nonzero(flat, size=capacity, fill_value=flat.size)[0].astype(jnp.int32)
    return ids, jnp.sum(flat, dtype=jnp.int32)
