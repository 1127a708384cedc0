"""Grid convergence: observed order, Richardson extrapolation and the Grid
Convergence Index (SPEC §5).

References
----------
* P. J. Roache 1998, *Verification and Validation in Computational Science
  and Engineering*, Hermosa, ch. 5 (Richardson extrapolation, GCI).
* I. B. Celik, U. Ghia, P. J. Roache, C. J. Freitas, H. Coleman, P. E. Raad
  2008, "Procedure for Estimation and Reporting of Uncertainty Due to
  Discretization in CFD Applications", J. Fluids Eng. 130, 078001 — the
  five-step procedure implemented by :func:`gci` (eqs. 1–10 there).

Conventions (Celik et al.): index 1 is the finest grid, h₁ < h₂ < h₃;
r₂₁ = h₂/h₁ > 1 and r₃₂ = h₃/h₂ > 1 (for N cells in d dimensions
r₂₁ = (N₁/N₂)^{1/d}); ε₂₁ = φ₂ − φ₁, ε₃₂ = φ₃ − φ₂.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from partmesh.compare.checks import number

__all__ = ["observed_order", "observed_order_three", "richardson", "gci"]

#: observed orders at or below this count as "no convergence".
_P_MIN = 1e-9
#: the bracket searched when the fixed-point iteration does not settle.
_P_BRACKET = (1e-6, 50.0)


def _ratio(name: str, r) -> float:
    r = number(name, r)
    if not r > 1.0:
        raise ValueError(f"{name} must be > 1 (coarse spacing over fine spacing), got {r:g}.")
    return r


def observed_order(h, errors) -> float:
    """Observed order of convergence from errors on two or more grids.

    The least-squares slope p of log e = log C + p log h over the levels,

        p = Σ (X − X̄)(Y − Ȳ) / Σ (X − X̄)²,  X = log h, Y = log e,

    which for two levels is p = log(e₂/e₁)/log(h₂/h₁) (Roache 1998, ch. 5).
    ``errors`` are errors against an exact or reference solution (e.g. the
    L1 norms of :func:`partmesh.compare.metrics.field_error`).

    Raises
    ------
    ValueError
        unless h and errors are 1D of equal length ≥ 2, h > 0 with at least
        two distinct values, and errors > 0, all finite.
    """
    h = np.asarray(h, dtype=float)
    e = np.asarray(errors, dtype=float)
    if h.ndim != 1 or h.size < 2:
        raise ValueError(f"h must be a 1D array of at least 2 grid spacings, got shape {h.shape}.")
    if e.shape != h.shape:
        raise ValueError(f"errors must have the shape of h {h.shape}, got {e.shape}.")
    if not np.all(np.isfinite(h)) or np.any(h <= 0):
        raise ValueError("h must hold finite spacings > 0.")
    if not np.all(np.isfinite(e)) or np.any(e <= 0):
        raise ValueError("errors must hold finite values > 0 (a zero error has no logarithm).")
    X, Y = np.log(h), np.log(e)
    dX = X - X.mean()
    sxx = float(np.sum(dX * dX))
    if sxx == 0.0:
        raise ValueError("h must hold at least two different spacings.")
    return float(np.sum(dX * (Y - Y.mean())) / sxx)


def _p_equation(p, ln_ratio, s, r21, r32):
    """Celik eqs. 3a–3c: p − |ln|ε₃₂/ε₂₁| + q(p)| / ln r₂₁."""
    q = math.log((r21**p - s) / (r32**p - s))
    return abs(ln_ratio + q) / math.log(r21)


def observed_order_three(f1, f2, f3, r21, r32, tol: float = 1e-15, max_iter: int = 500) -> float:
    """Apparent order p from three solutions, f1 on the finest grid.

    Celik et al. 2008, eqs. 3a–3c, for any refinement ratios:

        p = |ln|ε₃₂/ε₂₁| + q(p)| / ln r₂₁,
        q(p) = ln((r₂₁^p − s)/(r₃₂^p − s)),  s = sign(ε₃₂/ε₂₁),

    solved by fixed-point iteration from p₀ = |ln|ε₃₂/ε₂₁|| / ln r₂₁ (the
    exact answer for r₂₁ = r₃₂, where q = 0); if the iteration does not
    settle, the same equation is solved by bracketing (Brent) on
    p ∈ [1e-6, 50]. s = −1 flags oscillatory convergence.

    Raises
    ------
    ValueError
        for ratios ≤ 1, two equal consecutive solutions (ε₂₁ = 0 or ε₃₂ = 0,
        no order can be read), or an equation with no positive root (e.g.
        |ε₃₂| = |ε₂₁| on equal ratios: the solutions do not converge).
    """
    f1, f2, f3 = number("f1", f1), number("f2", f2), number("f3", f3)
    r21, r32 = _ratio("r21", r21), _ratio("r32", r32)
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0.0 or e32 == 0.0:
        raise ValueError("f1, f2, f3 must have f1 != f2 and f2 != f3 (equal solutions give no observed order).")
    s = 1.0 if e32 / e21 > 0 else -1.0
    ln_ratio = math.log(abs(e32 / e21))
    p = abs(ln_ratio) / math.log(r21)  # exact when r21 == r32 (q = 0)
    settled = False
    if p > _P_MIN:
        with np.errstate(all="ignore"):
            for _ in range(max_iter):  # a scalar fixed-point iteration, not a loop over data
                try:
                    pn = _p_equation(p, ln_ratio, s, r21, r32)
                except (ValueError, ZeroDivisionError, OverflowError):
                    break
                if not math.isfinite(pn) or pn <= 0:
                    break
                step = abs(pn - p)
                p = pn
                if step <= tol * max(1.0, p):
                    settled = True
                    break
            else:
                settled = step <= 1e-10 * max(1.0, p)  # settled at round-off
    if settled and p > _P_MIN:
        return p

    def g(pp):
        return pp - _p_equation(pp, ln_ratio, s, r21, r32)

    lo, hi = _P_BRACKET
    try:
        glo, ghi = g(lo), g(hi)
    except (ValueError, ZeroDivisionError, OverflowError):
        glo = ghi = float("nan")
    if not (glo * ghi < 0):
        raise ValueError(
            f"f1, f2, f3 = {f1:g}, {f2:g}, {f3:g} with r21={r21:g}, r32={r32:g} give no positive observed order."
        )
    return float(brentq(g, lo, hi, xtol=1e-14, rtol=4 * np.finfo(float).eps))



def richardson(f1, f2, r, p) -> float:
    """Richardson extrapolation to zero spacing from two grids.

        f_ext = f1 + (f1 − f2)/(r^p − 1) = (r^p f1 − f2)/(r^p − 1),

    f1 on the fine grid, f2 on the coarse grid, r = h2/h1 > 1, p > 0 the
    order (Roache 1998, ch. 5; Celik et al. 2008, eq. 4).

    Raises
    ------
    ValueError
        for r ≤ 1 or p ≤ 0.
    """
    f1, f2 = number("f1", f1), number("f2", f2)
    r = _ratio("r", r)
    p = number("p", p)
    if not p > 0:
        raise ValueError(f"p must be > 0, got {p:g}.")
    return f1 + (f1 - f2) / (r**p - 1.0)


def gci(f1, f2, f3, r21, r32, Fs: float = 1.25) -> dict:
    """Grid Convergence Index from three grids (Celik et al. 2008, §"Procedure").

    With p from :func:`observed_order_three` (Celik eqs. 3a–3c):

        f_ext    = (r₂₁^p f1 − f2)/(r₂₁^p − 1)               (eq. 4)
        e_a21    = |(f1 − f2)/f1|                             (eq. 5a)
        e_ext21  = |(f_ext − f1)/f_ext|                       (eq. 5b)
        gci_fine = Fs e_a21/(r₂₁^p − 1)                       (eq. 5c)
        gci_coarse = Fs e_a21 r₂₁^p/(r₂₁^p − 1)               (Roache 1998,
                     the GCI of the coarse grid 2 of the pair 21)
        gci_32   = Fs e_a32/(r₃₂^p − 1), e_a32 = |(f2 − f3)/f2|
        asymptotic_ratio = gci_32/(r₂₁^p gci_fine)            (≈ 1 in the
                     asymptotic range; Roache 1998)
        convergence_ratio R = ε₂₁/ε₃₂                          (0 < R < 1:
                     monotonic convergence, R < 0: oscillatory, R > 1 on equal
                     ratios: divergence — Celik's p is positive by construction,
                     so check R)

    Fs = 1.25 is the factor of safety for three-grid studies (Roache).

    Returns
    -------
    dict(p, f_ext, e_a21, e_ext21, gci_fine, gci_coarse, gci_32,
    asymptotic_ratio, convergence_ratio, oscillatory, r21, r32) — relative quantities as
    fractions (0.022 = 2.2 %); ``oscillatory`` is True when ε₃₂/ε₂₁ < 0.

    Raises
    ------
    ValueError
        for Fs ≤ 0, f1 = 0 or f2 = 0 (relative errors undefined), or the
        cases of :func:`observed_order_three`.
    """
    Fs = number("Fs", Fs)
    if not Fs > 0:
        raise ValueError(f"Fs must be > 0, got {Fs:g}.")
    p = observed_order_three(f1, f2, f3, r21, r32)
    f1, f2, f3 = float(f1), float(f2), float(f3)
    r21, r32 = float(r21), float(r32)
    if f1 == 0.0 or f2 == 0.0:
        raise ValueError("f1 and f2 must be non-zero (the GCI is relative to them).")
    rp = r21**p
    f_ext = (rp * f1 - f2) / (rp - 1.0)
    e_a21 = abs((f1 - f2) / f1)
    e_ext21 = abs((f_ext - f1) / f_ext) if f_ext != 0.0 else float("inf")
    gci_fine = Fs * e_a21 / (rp - 1.0)
    gci_coarse = Fs * e_a21 * rp / (rp - 1.0)
    e_a32 = abs((f2 - f3) / f2)
    gci_32 = Fs * e_a32 / (r32**p - 1.0)
    return dict(
        p=p, f_ext=f_ext, e_a21=e_a21, e_ext21=e_ext21, gci_fine=gci_fine, gci_coarse=gci_coarse,
        gci_32=gci_32, asymptotic_ratio=gci_32 / (rp * gci_fine) if gci_fine > 0 else float("nan"),
        convergence_ratio=(f2 - f1) / (f3 - f2), oscillatory=bool((f3 - f2) * (f2 - f1) < 0), r21=r21, r32=r32,
    )
