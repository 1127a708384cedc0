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
    return state, (np.int64(_mix(state) >> _S11) + 0.5) * _UNIT


def ziggurat_tables(f, f_inverse, layers, r, area):
    """Layer edges x_0 … x_layers and ratios x_{i+1}/x_i of a ziggurat for
    the decreasing density shape ``f`` on x ≥ 0 (Marsaglia & Tsang 2000,
    J. Stat. Softw. 5(8); Doornik 2005, "An improved ziggurat method to
    generate normal random samples"): ``layers`` strips of equal ``area``,
    the base strip (a pseudo-rectangle of width x_0 = area/f(r)) holding
    the tail beyond ``r``, x_layers = 0."""
    x = np.zeros(layers + 1)
    x[0], x[1] = area / f(r), r
    for i in range(2, layers):
        x[i] = f_inverse(area / x[i - 1] + f(x[i - 1]))
    return x, x[1:] / x[:-1]


#: normal: 128 layers (Doornik 2005)
NORMAL_R, NORMAL_AREA = 3.442619855899, 9.91256303526217e-3
_NORMAL_X, _NORMAL_RATIO = ziggurat_tables(lambda x: math.exp(-0.5 * x * x), lambda y: math.sqrt(-2.0 * math.log(y)),
                                           128, NORMAL_R, NORMAL_AREA)
#: exponential: 256 layers (Marsaglia & Tsang 2000)
EXPONENTIAL_R, EXPONENTIAL_AREA = 7.69711747013104972, 3.949659822581572e-3
_EXP_X, _EXP_RATIO = ziggurat_tables(lambda x: math.exp(-x), lambda y: -math.log(y), 256, EXPONENTIAL_R,
                                     EXPONENTIAL_AREA)


@numba.njit(cache=True, inline="always")
def normal(state):
    """``(state, z)``, z a standard normal, by the ziggurat: one 64-bit draw
    gives the layer (low 7 bits) and a uniform in (−1, 1) (high 53 bits);
    99 % of draws end at one comparison. The tail beyond r by Marsaglia's
    (1964) method."""
    while True:
        state = state + _GOLDEN
        bits = _mix(state)
        u = 2.0 * ((np.int64(bits >> _S11) + 0.5) * _UNIT) - 1.0
        i = int(bits & np.uint64(127))
        if abs(u) < _NORMAL_RATIO[i]:
            return state, u * _NORMAL_X[i]
        if i == 0:
            while True:
                state, u1 = uniform(state)
                state, u2 = uniform(state)
                t = math.log(u1) / NORMAL_R
                if -2.0 * math.log(u2) >= t * t:
                    return state, (t - NORMAL_R) if u < 0.0 else (NORMAL_R - t)
        z = u * _NORMAL_X[i]
        f0 = math.exp(-0.5 * (_NORMAL_X[i] * _NORMAL_X[i] - z * z))
        f1 = math.exp(-0.5 * (_NORMAL_X[i + 1] * _NORMAL_X[i + 1] - z * z))
        state, w = uniform(state)
        if f1 + w * (f0 - f1) < 1.0:
            return state, z


@numba.njit(cache=True, inline="always")
def exponential(state):
    """``(state, g)``, g ~ Exp(1), by the ziggurat (256 layers from the low
    8 bits, a uniform in (0, 1) from the high 53; 99 % of draws end at one
    comparison); the tail beyond r is r + Exp(1), the distribution having no
    memory."""
    tail = 0.0
    while True:
        state = state + _GOLDEN
        bits = _mix(state)
        u = (np.int64(bits >> _S11) + 0.5) * _UNIT
        i = int(bits & np.uint64(255))
        g = u * _EXP_X[i]
        if u < _EXP_RATIO[i]:
            return state, tail + g
        if i == 0:
            tail += EXPONENTIAL_R
            continue
        f0 = math.exp(g - _EXP_X[i])
        f1 = math.exp(g - _EXP_X[i + 1])
        state, w = uniform(state)
        if f1 + w * (f0 - f1) < 1.0:
            return state, tail + g


@numba.njit(cache=True)
def gamma(state, shape):
    """``(state, g)``: g ~ Gamma(shape, 1), shape > 0 (Marsaglia & Tsang
    2000, ACM TOMS 26, 363; for shape < 1 the draw at shape + 1 times
    u^(1/shape); for shape = 1, :func:`exponential`)."""
    if shape == 1.0:  # the exponential distribution (ζ = 2: a diatomic gas's rotational energy)
        return exponential(state)
    boost = 1.0
    if shape < 1.0:
        state, u = uniform(state)
        boost = u ** (1.0 / shape)
        shape += 1.0
    d = shape - 1.0 / 3.0
    c = 1.0 / math.sqrt(9.0 * d)
    while True:
        state, z = normal(state)
        t = 1.0 + c * z
        if t <= 0.0:
            continue
        t = t * t * t
        state, u = uniform(state)
        if math.log(u) < 0.5 * z * z + d - d * t + d * math.log(t):
            return state, d * t * boost
