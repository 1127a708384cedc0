r"""SPH smoothing kernels with compact support radius ``H``.

Every kernel is written in the *support* convention: ``W(r, H) = 0`` for
``r >= H`` and, with ``q = r/H`` in ``[0, 1)``,

.. math::

    W(r, H) &= \frac{\sigma_d}{H^d}\, f(q), \\
    \frac{\partial W}{\partial r} &= \frac{\sigma_d}{H^{d+1}}\, f'(q), \\
    \frac{\partial W}{\partial H} &= -\frac{\sigma_d}{H^{d+1}}\,\bigl(d\, f(q) + q\, f'(q)\bigr),

where ``d`` is the number of space dimensions (1, 2 or 3) and ``σ_d`` makes
``∫ W dV = 1``, i.e. ``1/σ_1 = ∫_{-1}^{1} f(|q|) dq``,
``1/σ_2 = 2π ∫_0^1 q f(q) dq`` and ``1/σ_3 = 4π ∫_0^1 q² f(q) dq``.

Kernels (``KERNELS`` maps the name to the integer id that the numba code
selects on):

============== ==================================================== ============== ========================
name           f(q)                                                 H / h          σ_1, σ_2, σ_3
============== ==================================================== ============== ========================
wendland_c6    (1−q)^8 (1 + 8q + 25q² + 32q³)                       2              15/8, 78/(7π), 1365/(64π)
wendland_c4    (1−q)^6 (1 + 6q + 35q²/3)                            2              27/16, 9/π, 495/(32π)
wendland_c2    (1−q)^4 (1 + 4q)                                     2              3/2, 7/π, 21/(2π)
cubic_spline   M4 with s = 2q (below)                               2              4/3, 40/(7π), 8/π
quintic_spline M6 with s = 3q (below)                               3              1/40, 63/(478π), 9/(40π)
gaussian       exp(−(3q)²), truncated at q = 1                      3              closed form with erf
============== ==================================================== ============== ========================

References
----------
* Wendland, H. (1995) Adv. Comput. Math. 4, 389–396 (the C2/C4/C6 functions
  ψ_{3,k}, positive definite in up to three dimensions, used here unchanged
  in 1D, 2D and 3D); Dehnen, W. & Aly, H. (2012) MNRAS 425, 1068 (the
  support-radius convention and the 2D/3D normalisations).
* Monaghan, J. J. & Lattanzio, J. C. (1985) A&A 149, 135 (M4 cubic spline);
  Morris, J. P. (1996) PhD thesis, Monash (M6 quintic spline normalisations
  1/120, 7/(478π), 1/(120π) in the h convention).
* Prasanna Kumar, Patnaik & Ramamurthi (2018) Phys. Fluids 30, 046105
  (Wendland C6 with n_f = 78/(7πH²) in 2D; the skewed kernel used for the
  wall-gradient treatment, SPEC §3.1).

Derivation of the 1D Wendland normalisations
--------------------------------------------
With the Beta integral ``∫_0^1 (1−q)^n q^k dq = k! n! / (n+k+1)!``:

* C6: ``∫_0^1 (1−q)^8 (1 + 8q + 25q² + 32q³) dq
  = 1/9 + 8/90 + 25/495 + 32/1980 = (220 + 176 + 100 + 32)/1980 = 4/15``,
  so ``∫_{-1}^{1} f(|q|) dq = 8/15`` and **σ_1 = 15/8**.
* C4: ``∫_0^1 (1−q)^6 (1 + 6q + 35q²/3) dq = 1/7 + 6/56 + (35/3)/252
  = (108 + 81 + 35)/756 = 8/27``, so **σ_1 = 27/16**.
* C2: ``∫_0^1 (1−q)^4 (1 + 4q) dq = 1/5 + 4/30 = 1/3``, so **σ_1 = 3/2**.

The same Beta integrals with an extra factor ``2πq`` give the SPEC's 2D value
``σ_2 = 78/(7π)`` for C6 (and 9/π, 7/π for C4, C2).

Splines in the support convention
---------------------------------
The M4 cubic spline is usually written ``W = σ^h_d / h^d · w(s)``, ``s = r/h``,
``w = 1 − 1.5 s² + 0.75 s³`` (s < 1), ``0.25 (2 − s)³`` (1 ≤ s < 2), with
``σ^h = 2/3, 10/(7π), 1/π``. With ``H = 2h`` and ``s = 2q``,
``W = σ^h_d 2^d / H^d · w(2q)``, hence ``σ_d = 2^d σ^h_d`` and
``f'(q) = 2 w'(s)``. The M6 quintic spline
``w = (3−s)^5 − 6(2−s)^5 + 15(1−s)^5`` (each term where its bracket is
positive), ``σ^h = 1/120, 7/(478π), 1/(120π)``, has ``H = 3h``, ``s = 3q`` and
``σ_d = 3^d σ^h_d``.

Truncated Gaussian
------------------
``f = exp(−9q²)`` (i.e. ``exp(−(r/h)²)`` with ``H = 3h``) cut at ``q = 1``;
its normalisation is that of the *truncated* function, in closed form:
``1/σ_1 = √π erf(3)/3``, ``1/σ_2 = π(1 − e^{−9})/9``,
``1/σ_3 = (4π/27)(√π erf(3)/4 − 1.5 e^{−9})``. The kernel jumps by
``σ_d e^{−9}/H^d`` (≈ 1.2e−4 of its central value) at ``r = H``; the
derivatives returned are those of the smooth part.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange

from partmesh.cases.errors import InputError
from partmesh.particle.threads import PRANGE_ONLY

__all__ = [
    "KERNELS",
    "SIGMA",
    "dwdh",
    "dwdr",
    "kernel_dwdh",
    "kernel_dwdr",
    "kernel_eval",
    "kernel_id",
    "kernel_w",
    "least_eta",
    "sigma",
    "skewed_grad",
    "skewed_w",
    "support_ratio",
    "w",
]

KERNELS: dict[str, int] = {
    "wendland_c6": 0,
    "wendland_c4": 1,
    "wendland_c2": 2,
    "cubic_spline": 3,
    "quintic_spline": 4,
    "gaussian": 5,
}

WENDLAND_C6 = KERNELS["wendland_c6"]
WENDLAND_C4 = KERNELS["wendland_c4"]
WENDLAND_C2 = KERNELS["wendland_c2"]
CUBIC_SPLINE = KERNELS["cubic_spline"]
QUINTIC_SPLINE = KERNELS["quintic_spline"]
GAUSSIAN = KERNELS["gaussian"]

# H / h: the support radius in units of the conventional smoothing length h.
_SUPPORT_RATIO: dict[str, float] = {
    "wendland_c6": 2.0,
    "wendland_c4": 2.0,
    "wendland_c2": 2.0,
    "cubic_spline": 2.0,
    "quintic_spline": 3.0,
    "gaussian": 3.0,
}

_PI = math.pi
_E9 = math.exp(-9.0)
_ERF3 = math.erf(3.0)

# SIGMA[kind, d]: normalisation σ_d in the support convention (column 0 unused).
SIGMA = np.array(
    [
        # wendland_c6
        [0.0, 15.0 / 8.0, 78.0 / (7.0 * _PI), 1365.0 / (64.0 * _PI)],
        # wendland_c4
        [0.0, 27.0 / 16.0, 9.0 / _PI, 495.0 / (32.0 * _PI)],
        # wendland_c2
        [0.0, 3.0 / 2.0, 7.0 / _PI, 21.0 / (2.0 * _PI)],
        # cubic_spline: 2^d × (2/3, 10/(7π), 1/π)
        [0.0, 2.0 * 2.0 / 3.0, 4.0 * 10.0 / (7.0 * _PI), 8.0 / _PI],
        # quintic_spline: 3^d × (1/120, 7/(478π), 1/(120π))
        [0.0, 3.0 / 120.0, 9.0 * 7.0 / (478.0 * _PI), 27.0 / (120.0 * _PI)],
        # gaussian truncated at q = 1 (H = 3h)
        [
            0.0,
            3.0 / (math.sqrt(_PI) * _ERF3),
            9.0 / (_PI * (1.0 - _E9)),
            27.0 / (4.0 * _PI * (0.25 * math.sqrt(_PI) * _ERF3 - 1.5 * _E9)),
        ],
    ],
    dtype=np.float64,
)
SIGMA.setflags(write=False)


# --------------------------------------------------------------------------
# numba scalar kernels
# --------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def shape(kind, q):
    """Shape function f(q) for 0 ≤ q < 1 (no range check)."""
    if kind == 0:
        t = 1.0 - q
        t2 = t * t
        t4 = t2 * t2
        return t4 * t4 * (1.0 + q * (8.0 + q * (25.0 + 32.0 * q)))
    elif kind == 1:
        t = 1.0 - q
        t2 = t * t
        return t2 * t2 * t2 * (1.0 + q * (6.0 + q * (35.0 / 3.0)))
    elif kind == 2:
        t = 1.0 - q
        t2 = t * t
        return t2 * t2 * (1.0 + 4.0 * q)
    elif kind == 3:
        s = 2.0 * q
        if s < 1.0:
            return 1.0 - s * s * (1.5 - 0.75 * s)
        t = 2.0 - s
        return 0.25 * t * t * t
    elif kind == 4:
        s = 3.0 * q
        t3 = 3.0 - s
        t3sq = t3 * t3
        val = t3sq * t3sq * t3
        if s < 2.0:
            t2 = 2.0 - s
            t2sq = t2 * t2
            val -= 6.0 * t2sq * t2sq * t2
            if s < 1.0:
                t1 = 1.0 - s
                t1sq = t1 * t1
                val += 15.0 * t1sq * t1sq * t1
        return val
    else:
        return math.exp(-9.0 * q * q)


@numba.njit(cache=True, inline="always")
def shape_derivative(kind, q):
    """Derivative f'(q) for 0 ≤ q < 1 (no range check)."""
    if kind == 0:
        # f' = −22 q (1−q)^7 (1 + 7q + 16q²)
        t = 1.0 - q
        t2 = t * t
        t4 = t2 * t2
        return -22.0 * q * t4 * t2 * t * (1.0 + q * (7.0 + 16.0 * q))
    elif kind == 1:
        # f' = −(56/3) q (1−q)^5 (1 + 5q)
        t = 1.0 - q
        t2 = t * t
        return -(56.0 / 3.0) * q * t2 * t2 * t * (1.0 + 5.0 * q)
    elif kind == 2:
        # f' = −20 q (1−q)^3
        t = 1.0 - q
        return -20.0 * q * t * t * t
    elif kind == 3:
        s = 2.0 * q
        if s < 1.0:
            return 2.0 * s * (-3.0 + 2.25 * s)
        t = 2.0 - s
        return 2.0 * (-0.75 * t * t)
    elif kind == 4:
        s = 3.0 * q
        t3 = 3.0 - s
        t3sq = t3 * t3
        val = -5.0 * t3sq * t3sq
        if s < 2.0:
            t2 = 2.0 - s
            t2sq = t2 * t2
            val += 30.0 * t2sq * t2sq
            if s < 1.0:
                t1 = 1.0 - s
                t1sq = t1 * t1
                val -= 75.0 * t1sq * t1sq
        return 3.0 * val
    else:
        return -18.0 * q * math.exp(-9.0 * q * q)


@numba.njit(cache=True, inline="always")
def _hpow(H, dim):
    if dim == 1:
        return H
    elif dim == 2:
        return H * H
    return H * H * H


@numba.njit(cache=True)
def kernel_w(kind, r, H, dim):
    r"""Kernel value ``W(r, H) = σ_d / H^d · f(r/H)`` (0 for ``r ≥ H``).

    ``kind`` is an id from :data:`KERNELS`, ``r ≥ 0`` the distance, ``H > 0``
    the compact support radius, ``dim`` ∈ {1, 2, 3}. No input checking (hot
    path); see the module docstring for f, σ_d and references (Wendland 1995;
    Dehnen & Aly 2012; Monaghan & Lattanzio 1985).
    """
    q = r / H
    if q >= 1.0:
        return 0.0
    return SIGMA[kind, dim] / _hpow(H, dim) * shape(kind, q)


@numba.njit(cache=True)
def kernel_dwdr(kind, r, H, dim):
    r"""Radial derivative ``∂W/∂r = σ_d / H^(d+1) · f'(r/H)`` (0 for ``r ≥ H``).

    The gradient is ``∇_i W(r_ij) = ∂W/∂r · (x_i − x_j)/r``. Arguments as in
    :func:`kernel_w` (Dehnen & Aly 2012, eq. 3 convention).
    """
    q = r / H
    if q >= 1.0:
        return 0.0
    return SIGMA[kind, dim] / (_hpow(H, dim) * H) * shape_derivative(kind, q)


@numba.njit(cache=True)
def kernel_dwdh(kind, r, H, dim):
    r"""Derivative with respect to the support radius,
    ``∂W/∂H = −σ_d / H^(d+1) · (d f(q) + q f'(q))``, ``q = r/H`` (0 for ``q ≥ 1``).

    Used for the grad-h term Ω of Springel & Hernquist (2002) / Price (2012)
    (SPEC §3.1). Arguments as in :func:`kernel_w`. For ``h = H / support_ratio``
    use ``∂W/∂h = support_ratio · ∂W/∂H``.
    """
    q = r / H
    if q >= 1.0:
        return 0.0
    return -SIGMA[kind, dim] / (_hpow(H, dim) * H) * (dim * shape(kind, q) + q * shape_derivative(kind, q))


@numba.njit(cache=True)
def kernel_eval(kind, r, H, dim):
    r"""``(W, ∂W/∂r, ∂W/∂H)`` at once, sharing q, f and f'.

    ``W = σ_d/H^d f(q)``, ``∂W/∂r = σ_d/H^(d+1) f'(q)``,
    ``∂W/∂H = −σ_d/H^(d+1) (d f + q f')`` with ``q = r/H``; all three are 0
    for ``q ≥ 1``. Arguments as in :func:`kernel_w`.
    """
    q = r / H
    if q >= 1.0:
        return 0.0, 0.0, 0.0
    s = SIGMA[kind, dim] / _hpow(H, dim)
    fq = shape(kind, q)
    dfq = shape_derivative(kind, q)
    return s * fq, s / H * dfq, -s / H * (dim * fq + q * dfq)


@numba.njit(cache=True)
def skewed_w(kind, rx, ry, H, dim, lam_x, lam_y):
    r"""Skewed kernel ``W_s = W(|r|, H) (1 + erf(λ·R))``, ``R = r_vec / H``.

    After Prasanna Kumar, Patnaik & Ramamurthi (2018), SPEC §3.1.
    ``r_vec = (rx, ry)`` is the separation ``x_i − x_j`` (the ``dx`` convention
    of :func:`partmesh.particle.neighbours.neighbours`; pass ``ry = 0`` in 1D) and
    ``λ = (lam_x, lam_y)``. Because erf is odd, ``W_s(R) + W_s(−R) = 2 W(|R|)``
    and ``∫ W_s dV = ∫ W dV = 1``; ``W_s → 2W`` where ``λ·R ≫ 0`` and ``→ 0``
    where ``λ·R ≪ 0``. With ``λ = −c n̂`` (``n̂`` the wall normal pointing
    into the fluid, c = 10) a neighbour j on the fluid side
    (``x_j − x_i`` along ``+n̂``) has ``λ·R > 0`` and keeps its weight, one
    on the solid side has ``λ·R < 0`` and is switched off.
    """
    r = math.sqrt(rx * rx + ry * ry)
    wv = kernel_w(kind, r, H, dim)
    if wv == 0.0:
        return 0.0
    return wv * (1.0 + math.erf((lam_x * rx + lam_y * ry) / H))


@numba.njit(cache=True)
def skewed_grad(kind, rx, ry, H, dim, lam_x, lam_y):
    r"""Gradient of the skewed kernel with respect to ``r_vec = x_i − x_j``:

    ``∇W_s = ∂W/∂r · r̂ (1 + erf(λ·R)) + W · (2/√π) exp(−(λ·R)²) λ / H``,
    ``R = r_vec / H`` (Prasanna Kumar et al. 2018, SPEC §3.1). Returns
    ``(gx, gy)``; ``gy`` is 0 in 1D when ``ry = lam_y = 0``.
    """
    r = math.sqrt(rx * rx + ry * ry)
    q = r / H
    if q >= 1.0:
        return 0.0, 0.0
    wv, dw, _ = kernel_eval(kind, r, H, dim)
    arg = (lam_x * rx + lam_y * ry) / H
    skew = 1.0 + math.erf(arg)
    dskew = 2.0 / math.sqrt(math.pi) * math.exp(-arg * arg) / H
    gx = wv * dskew * lam_x
    gy = wv * dskew * lam_y
    if r > 0.0:
        gx += dw * skew * rx / r
        gy += dw * skew * ry / r
    return gx, gy


# --------------------------------------------------------------------------
# numpy-level wrappers
# --------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def _eval_one(kind, r, H, dim, which):
    """W (which 0), ∂W/∂r (1) or ∂W/∂H (2)."""
    if which == 0:
        return kernel_w(kind, r, H, dim)
    elif which == 1:
        return kernel_dwdr(kind, r, H, dim)
    return kernel_dwdh(kind, r, H, dim)


@numba.njit(cache=True, parallel=PRANGE_ONLY)
def _eval_many(kind, r, H, dim, which, out):
    for k in prange(r.size):
        out[k] = _eval_one(kind, r[k], H[k], dim, which)


@numba.njit(cache=True)
def _eval_few(kind, r, H, dim, which, out):
    for k in range(r.size):
        out[k] = _eval_one(kind, r[k], H[k], dim, which)


_PARALLEL_MIN = 20000  # below this, starting the thread pool costs more than it saves


def kernel_id(name) -> int:
    """Integer id of kernel ``name`` (a key of :data:`KERNELS`) for numba code."""
    if isinstance(name, (int, np.integer)) and not isinstance(name, bool):
        if int(name) in KERNELS.values():
            return int(name)
    elif name in KERNELS:
        return KERNELS[name]
    raise InputError(f"kernel must be one of {', '.join(KERNELS)}; got {name!r}.")


def _check_dim(dim) -> int:
    if isinstance(dim, bool) or not isinstance(dim, (int, np.integer)) or dim not in (1, 2, 3):
        raise InputError(f"dim must be 1, 2 or 3; got {dim!r}.")
    return int(dim)


def _prepare(name, r, H, dim):
    kind = kernel_id(name)
    dim = _check_dim(dim)
    try:
        r = np.asarray(r, dtype=np.float64)
        H = np.asarray(H, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("r and H must be numeric arrays.") from None
    if not np.all(np.isfinite(r)) or np.any(r < 0):
        raise InputError("r must be finite and >= 0 (a distance).")
    if not np.all(np.isfinite(H)) or np.any(H <= 0):
        raise InputError("H (the kernel support radius) must be finite and > 0.")
    try:
        rb, Hb = np.broadcast_arrays(r, H)
    except ValueError:
        raise InputError(f"r (shape {r.shape}) and H (shape {H.shape}) must broadcast together.") from None
    return kind, dim, np.ascontiguousarray(rb).ravel(), np.ascontiguousarray(Hb).ravel(), rb.shape


def _vectorised(which, name, r, H, dim):
    kind, dim, rf, Hf, shape = _prepare(name, r, H, dim)
    out = np.empty(rf.size, dtype=np.float64)
    (_eval_many if rf.size >= _PARALLEL_MIN else _eval_few)(kind, rf, Hf, dim, which, out)
    if shape == ():
        return float(out[0])
    return out.reshape(shape)


def w(name, r, H, dim):
    r"""Kernel ``W(r, H) = σ_d / H^d · f(r/H)`` on arrays (broadcast ``r`` and ``H``).

    ``name`` a key of :data:`KERNELS`, ``r ≥ 0``, ``H > 0`` the support radius,
    ``dim`` ∈ {1, 2, 3}. Returns a float for scalar input. Normalised so that
    ``∫ W dV = 1`` (references in the module docstring).
    """
    return _vectorised(0, name, r, H, dim)


def dwdr(name, r, H, dim):
    r"""``∂W/∂r = σ_d / H^(d+1) · f'(r/H)`` on arrays; arguments as in :func:`w`."""
    return _vectorised(1, name, r, H, dim)


def dwdh(name, r, H, dim):
    r"""``∂W/∂H = −σ_d / H^(d+1) · (d f(q) + q f'(q))``, ``q = r/H``, on arrays;
    arguments as in :func:`w`."""
    return _vectorised(2, name, r, H, dim)


def support_ratio(name) -> float:
    r"""``H / h``: the support radius in units of the kernel's conventional
    smoothing length ``h`` (2 for the Wendland kernels, written on ``q_h = r/h ≤ 2``
    as in SPEC §3.2 and Dehnen & Aly 2012, and for the M4 cubic spline; 3 for
    the M6 quintic spline and for the Gaussian ``exp(−(r/h)²)`` cut at 3h)."""
    kind = kernel_id(name)
    key = next(k for k, v in KERNELS.items() if v == kind)
    return _SUPPORT_RATIO[key]


def sigma(name, dim) -> float:
    """Normalisation ``σ_d`` of kernel ``name`` in ``dim`` dimensions, support
    convention: ``W = σ_d / H^d · f(r/H)``."""
    return float(SIGMA[kernel_id(name), _check_dim(dim)])


def least_eta(name, dim) -> float:
    r"""The support radius in local spacings, ``η = H (ρ/m)^(1/d)``, at and
    below which the summation density has no solution with kernel ``name``
    in ``dim`` dimensions: ``η_min = (σ_d f(0))^(1/d)``.

    A particle's own term alone gives ``Σ_j m_j W(r_ij, H) ≥ m_i σ_d f(0)/H^d``
    (every ``W ≥ 0``), while ``H = η (m_i/ρ_i)^(1/d)`` asks for
    ``ρ_i = m_i η^d/H^d``: for ``η^d ≤ σ_d f(0)`` the sum exceeds it at
    every ``H`` and the support shrinks without end (Price 2012, J. Comput.
    Phys. 231, 759, §2.3, on the joint solve)."""
    kind, d = kernel_id(name), _check_dim(dim)
    return float((SIGMA[kind, d] * shape(kind, 0.0)) ** (1.0 / d))
