"""Counter-based random streams for the DSMC kernels (numba).

Every stream is keyed by ``(seed, step, key)`` — for the equilibrium redraw
the key is the cell — and advanced with SplitMix64 (Steele, Lea & Flood
2014, "Fast splittable pseudorandom number generators", OOPSLA; the
64-bit finaliser of Stafford's "Mix13"). A cell draws the same numbers
whichever thread handles it and however many threads there are, so a run
is reproducible from its seed alone.

The state is a ``uint64``; every function returns the advanced state with
its draw, so the kernels thread it through explicitly.
"""

from __future__ import annotations

import math

import numba
import numpy as np

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
_STEP_KEY = np.uint64(0xD1B54A32D192ED03)
_CELL_KEY = np.uint64(0x8CB92BA72F3D8DD7)
_S30, _S27, _S31, _S11 = np.uint64(30), np.uint64(27), np.uint64(31), np.uint64(11)
#: 2⁻⁵³: a 53-bit integer times this is a double in [0, 1)
_UNIT = 1.0 / 9007199254740992.0


@numba.njit(cache=True, inline="always")
def _mix(z):
    """Stafford's Mix13 finaliser: a bijection of uint64 with full avalanche."""
    z = (z ^ (z >> _S30)) * _M1
    z = (z ^ (z >> _S27)) * _M2
    return z ^ (z >> _S31)


@numba.njit(cache=True, inline="always")
def stream(seed, step, key):
    """The starting state of the stream keyed by ``(seed, step, key)``
    (non-negative integers)."""
    z = _mix(np.uint64(seed) + _GOLDEN)
    z = _mix(z ^ (np.uint64(step) * _STEP_KEY))
    return _mix(z ^ (np.uint64(key) * _CELL_KEY))


@numba.njit(cache=True, inline="always")
def uniform(state):
    """``(state, u)``, u uniform in the open interval (0, 1) (53 bits)."""
    state = state + _GOLDEN
    return state, ((_mix(state) >> _S11) + 0.5) * _UNIT


@numba.njit(cache=True, inline="always")
def normal_pair(state):
    """``(state, z0, z1)``: two independent standard normals (Box–Muller)."""
    state, u0 = uniform(state)
    state, u1 = uniform(state)
    radius = math.sqrt(-2.0 * math.log(u0))
    return state, radius * math.cos(2.0 * math.pi * u1), radius * math.sin(2.0 * math.pi * u1)


@numba.njit(cache=True)
def gamma(state, shape):
    """``(state, g)``: g ~ Gamma(shape, 1), shape > 0 (Marsaglia & Tsang
    2000, ACM TOMS 26, 363; for shape < 1 the draw at shape + 1 times
    u^(1/shape))."""
    boost = 1.0
    if shape < 1.0:
        state, u = uniform(state)
        boost = u ** (1.0 / shape)
        shape += 1.0
    d = shape - 1.0 / 3.0
    c = 1.0 / math.sqrt(9.0 * d)
    while True:
        state, z, _ = normal_pair(state)
        t = 1.0 + c * z
        if t <= 0.0:
            continue
        t = t * t * t
        state, u = uniform(state)
        if math.log(u) < 0.5 * z * z + d - d * t + d * math.log(t):
            return state, d * t * boost
