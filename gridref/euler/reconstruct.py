"""Limited piecewise-linear reconstruction (van Leer 1979; Toro 2009 §13.4).

A limiter maps the backward and forward differences ``a = W_i − W_{i−1}``,
``b = W_{i+1} − W_i`` to a limited slope (per cell, per variable).
"""

from __future__ import annotations

import jax.numpy as jnp


def minmod(a, b):
    """``minmod(a, b)``: the smaller in magnitude where signs agree, else 0."""
    return jnp.where(a * b > 0.0, jnp.where(jnp.abs(a) < jnp.abs(b), a, b), 0.0)


def monotonized_central(a, b):
    """MC limiter (van Leer 1977): ``minmod(2a, 2b, (a+b)/2)``."""
    central = 0.5 * (a + b)
    bound = 2.0 * jnp.minimum(jnp.abs(a), jnp.abs(b))
    return jnp.where(a * b > 0.0, jnp.sign(central) * jnp.minimum(jnp.abs(central), bound), 0.0)


def van_leer(a, b):
    """van Leer's harmonic limiter: ``2ab/(a+b)`` where ``ab > 0``, else 0."""
    ab = a * b
    return jnp.where(ab > 0.0, 2.0 * ab / jnp.where(ab > 0.0, a + b, 1.0), 0.0)


def superbee(a, b):
    """Roe's superbee: ``sign · max(min(2|a|,|b|), min(|a|,2|b|))`` where ``ab > 0``."""
    s = jnp.sign(a)
    A, B = jnp.abs(a), jnp.abs(b)
    return jnp.where(a * b > 0.0, s * jnp.maximum(jnp.minimum(2.0 * A, B), jnp.minimum(A, 2.0 * B)), 0.0)


def first_order(a, b):
    """Zero slope: piecewise-constant states, Godunov's first-order scheme
    (with ``riemann="efm"``, the deterministic limit of the equilibrium
    DSMC on the same cells)."""
    return jnp.zeros_like(a)


LIMITERS = {"minmod": minmod, "mc": monotonized_central, "vanleer": van_leer, "superbee": superbee,
            "first_order": first_order}


def limited_slopes(W, axis, limiter):
    """Limited slopes along ``axis`` for every cell except the first and last
    along that axis (the result is two cells shorter there)."""
    n = W.shape[axis]
    lo = [slice(None)] * W.ndim
    mid = [slice(None)] * W.ndim
    hi = [slice(None)] * W.ndim
    lo[axis], mid[axis], hi[axis] = slice(0, n - 2), slice(1, n - 1), slice(2, n)
    Wm = W[tuple(mid)]
    return limiter(Wm - W[tuple(lo)], W[tuple(hi)] - Wm)
