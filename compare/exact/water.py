"""Linear water waves from an initial elevation at rest (the Cauchy–Poisson
problem, finite depth), planar and radial, with and without dispersion.
The shallow-water dam break is in :mod:`partmesh.compare.exact.stoker_ritter`.

Linear dispersive waves
-----------------------
Water of still depth d, at rest at t = 0 with free-surface elevation
eta0, flat bed, gravity g; linear (small amplitude) potential flow. Each
Fourier (planar) or Hankel (radial) component of eta0 oscillates as a
standing wave with the finite-depth dispersion relation
omega^2 = g k tanh(k d) (Whitham 1974, "Linear and Nonlinear Waves", §13;
Mei 1989, "The Applied Dynamics of Ocean Surface Waves", ch. 2):

* planar, eta0 even in x (a reflecting wall or symmetry plane at x = 0)::

      eta(x, t) = (1/pi) int_0^inf F(k) cos(k x) cos(omega t) dk,
      F(k) = 2 int_0^inf eta0(x) cos(k x) dx;

* radial, axisymmetric about r = 0 (Hankel pair)::

      eta(r, t) = int_0^inf G(k) J0(k r) cos(omega t) k dk,
      G(k) = int_0^inf eta0(r) J0(k r) r dr.

The depth-averaged velocity follows from linear mass conservation,
d eta/dt + d div(u) = 0::

      u(x, t) = (1/pi) int_0^inf F(k) sin(k x) (omega/(k d)) sin(omega t) dk,
      u(r, t) = int_0^inf G(k) J1(k r) (omega/(k d)) sin(omega t) k dk.

With ``dispersive=False`` the same integrals are taken with
omega = k sqrt(g d) (the linear shallow-water / wave equation); in planar
geometry that is d'Alembert's eta = [eta0e(x - c t) + eta0e(x + c t)]/2 with
eta0e the even extension and c = sqrt(g d).

Initial shapes are in :mod:`partmesh.compare.exact.initial_elevations`.

Quadrature
~~~~~~~~~~
The integrands oscillate like exp(i theta(k)) with phase
theta = k b +- omega(k) t, b = e +- x the distance between the point and an
edge e of the initial shape (a discontinuity of eta0 or of a derivative),
and the transform of a discontinuous shape decays only like 1/k. The
integral is split at a cut-off K:

1. [0, K] is covered by panels on which the phase
   (max b) k + omega(k) t_max advances by at most 3 pi, with 16-point
   Gauss-Legendre on each (about 10 nodes per oscillation). With dispersion
   a panel is also no wider than (1 + k d/4)/d, which keeps the poles of
   tanh(k d) (at k d = i pi/2) and the branch point of sqrt(g k) at k = 0
   far from every panel.
2. [K, inf) is done analytically. Each shape writes its transform exactly as
   Re sum_e a_e(k) exp(i k e) with slowly varying a_e (for Bessel functions
   through the scaled Hankel function, J_nu(z) = Re[hankel1e(nu, z) e^(i z)]);
   the kernels cos(kx), sin(kx), J0(kr), J1(kr) and cos(omega t),
   sin(omega t) are written the same way, so the tail is a sum of
   int_K^inf C(k) exp(i theta(k)) dk with slowly varying C. Without a
   stationary point of theta beyond K, two integrations by parts give
   -exp(i theta(K)) [Phi(K) - Phi'(K)/(i theta'(K))], Phi = C/(i theta')
   (Phi' by a central difference), with a remainder of about
   |C(K)| q^2/(K^2 |theta'|^3), q ~ 3.
3. K is chosen per point and time. The group velocity
   c_g = d omega/dk <= sqrt(g d) falls with k, so the short waves from an
   edge reach a point at distance |b| only when c_g(k) t = |b|: K is at
   least the wavenumber where c_g(K) t = |b|/1.5, which keeps every
   stationary point (k_s, where the short waves that arrive by t sit) inside
   [0, K] (K >= 2.25 k_s in deep water) and |theta'| >= |b|/3 on the tail.
   K (a power of 2 times 4/L, L the size of the shape) is then raised until
   the remainder estimate 9 |C(K)| / (K^2 |theta'|^3) is below ``tol``
   times max|eta0| for every edge. Without dispersion c_g = sqrt(g d) for
   all k and |theta'| >= ||b| - sqrt(g d) t|, the distance to the moving
   discontinuity of d'Alembert's solution.
4. Points and times that share a cut-off are computed together (one matrix
   product of kernel values and time factors per group).

Error bound: outside the bands below, the truncation error is about ``tol``
x max|eta0| per edge and term (1e-7 by default) and the panel error is
smaller still. At the scene gauges over 20 s (Prins' box; the crater,
planar and radial) eta changes by at most 2e-8 of the amplitude when the
node density and K are doubled and ``tol`` is lowered to 1e-10, and a
brute-force quadrature of Prins' box to k = 2e6 without tail agrees within
5e-8 Q; the results meet the 1e-4 max|eta0| asked of a reference with a
wide margin.

Gibbs bands: an exact reconstruction of a discontinuous eta0 from its
transform is impossible at the discontinuity itself. At t = 0, and for all
t without dispersion (where the discontinuity moves at sqrt(g d)), the
needed K grows like 1/a with the distance a to the discontinuity; with
dispersion it grows like t^2/a^2 (the ripples near an edge at time t have
k ~ g t^2/(4 a^2)). K is capped at ``k_max`` (default 2^17/L: 2.1e5 rad/m
for Prins' box); at points closer than that to an edge the result is the
cap's truncation, not a converged value (``return_resolved=True`` marks
them). For the defaults the band reaches about 2 mm from an edge at t = 0
and, with dispersion, 0.75 sqrt(g/k_max) t from an edge in deep water
(about 0.005 t m, t in seconds, for Prins' box).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import xarray as xr
from scipy.special import hankel1e, j0, j1

from partmesh.compare.checks import in_range
from partmesh.compare.exact._inputs import axis, output_times, positive
from partmesh.compare.exact.initial_elevations import (
    GEOMETRIES,
    Crater,
    Edge,
    Gaussian,
    InitialShape,
    Mound,
    checked_geometry,
)
from partmesh.compare.schema import result

__all__ = [
    "CRATER_GAUGES", "GEOMETRIES", "GRAVITY", "PRINS_GAUGES", "Crater", "Edge", "Gaussian", "InitialShape", "Mound",
    "dispersion", "group_velocity", "linear_wave_fields", "linear_waves", "standing_wave", "standing_wave_fields",
]

#: gravitational acceleration [m s-2]
GRAVITY = 9.81
#: gauge positions [m] of Prins (1958), still depth 0.7 m
PRINS_GAUGES = (2.0, 4.57, 6.0, 8.0)
#: gauge radii [m] of the crater (cavity collapse) scene, still depth 1.0 m
CRATER_GAUGES = (2.0, 4.0, 6.0)

#: Gauss-Legendre nodes and weights on [-1, 1] used on each panel
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)
#: largest phase advance over one panel
_PANEL_PHASE = 3.0 * np.pi
#: c_g(K) t <= |b| / _MARGIN keeps every stationary point below K
_MARGIN = 1.5
#: relative step of the central difference in the tail's second term
_DELTA = 1e-3
#: numbers of kernel x node values per block of the matrix products
_CHUNK = 2_000_000


# ----------------------------------------------------------------------------------------------------------------
# dispersion


def _omega(k, d, g, dispersive):
    k = np.asarray(k, dtype=float)
    if not dispersive:
        return math.sqrt(g * d) * k
    return np.sqrt(g * k * np.tanh(k * d))


def _group_velocity(k, d, g, dispersive):
    c0 = math.sqrt(g * d)
    k = np.asarray(k, dtype=float)
    if not dispersive:
        return np.full_like(k, c0)
    kd = k * d
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        phase = np.where(k > 0.0, np.sqrt(g * np.tanh(kd) / k), c0)
        # 2 kd / sinh(2 kd), written without overflow and exact at kd -> 0
        factor = np.where(kd > 0.0, 4.0 * kd * np.exp(-2.0 * kd) / -np.expm1(-4.0 * kd), 1.0)
    return 0.5 * phase * (1.0 + factor)


def dispersion(k, d, g: float = GRAVITY, dispersive: bool = True):
    """Angular frequency omega(k) = sqrt(g k tanh(k d)) of linear water waves (Whitham 1974, §13).

    ``dispersive=False`` gives the shallow-water limit omega = k sqrt(g d).
    Vectorised over ``k`` (>= 0, rad/m); ``d`` > 0 the still depth [m].
    """
    d, g = positive("d", d), positive("g", g)
    return _omega(_wavenumbers(k), d, g, dispersive)


def group_velocity(k, d, g: float = GRAVITY, dispersive: bool = True):
    """Group velocity c_g = d omega/dk = (omega/(2k)) (1 + 2kd/sinh(2kd)) (Whitham 1974, §13).

    Falls monotonically from sqrt(g d) at k = 0 to (1/2) sqrt(g/k) in deep
    water; sqrt(g d) for all k with ``dispersive=False``.
    """
    d, g = positive("d", d), positive("g", g)
    return _group_velocity(_wavenumbers(k), d, g, dispersive)


def _wavenumbers(k):
    k = np.asarray(k, dtype=float)
    if not np.all(np.isfinite(k)) or np.any(k < 0.0):
        raise ValueError("k must be finite and >= 0.")
    return k


def _inverse_group_velocity(v, d, g):
    """The wavenumber where c_g(k) = v (dispersive), 0 where v >= sqrt(g d)."""
    c0 = math.sqrt(g * d)
    kd = np.logspace(-6.0, 12.0, 3601)
    ratio = _group_velocity(kd / d, d, g, True) / c0  # decreasing
    v = np.asarray(v, dtype=float) / c0
    with np.errstate(divide="ignore"):
        log_kd = np.interp(-np.log(np.maximum(v, 1e-300)), -np.log(ratio), np.log(kd))
    k = np.exp(log_kd) / d
    deep = v < ratio[-1]
    with np.errstate(divide="ignore"):
        k = np.where(deep, g / (4.0 * (v * c0) ** 2), k)
    return np.where(v >= 1.0, 0.0, k)


# ----------------------------------------------------------------------------------------------------------------
# linear waves: quadrature


def _kernels(k, r, geometry):
    """Kernel values for eta and u at wavenumbers k (shape (..., n)) and distances r."""
    kr = k * r
    if geometry == "planar":
        return np.cos(kr), np.sin(kr)
    return j0(kr), j1(kr)


def _kernel_amplitudes(k, r, geometry):
    """a such that kernel = Re[a exp(i k r)] for the eta and the u kernel (r >= 0)."""
    shape = np.broadcast(k, r).shape
    if geometry == "planar":
        return np.ones(shape, complex), np.full(shape, -1j)
    on_axis = r == 0.0
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        kr = np.where(on_axis, 1.0, k * r)
        return (np.where(on_axis, 1.0 + 0j, hankel1e(0, kr)), np.where(on_axis, 0j, hankel1e(1, kr)))


def _measure(k, geometry):
    return np.full_like(k, 1.0 / np.pi) if geometry == "planar" else k


class _Problem(NamedTuple):
    shape: InitialShape
    geometry: str
    d: float
    g: float
    dispersive: bool


def _levels(p: _Problem, r, t, ladder, tol):
    """Index into ``ladder`` of the cut-off each (time, point) pair needs, and whether it is within the ladder."""
    edges = p.shape.edges(p.geometry)
    n_levels = len(ladder)
    if not edges:
        return np.zeros((t.size, r.size), int), np.ones((t.size, r.size), bool)
    level = np.zeros((t.size, r.size), int)
    c0 = math.sqrt(p.g * p.d)
    for edge in edges:
        slope_lo = np.full((t.size, r.size), np.inf)
        k_stat = np.zeros((t.size, r.size))
        for b in (edge.position + r, edge.position - r):
            b = np.abs(b)[None, :]
            if p.dispersive:
                moving = t[:, None] > 0.0
                slope_lo = np.minimum(slope_lo, np.where(moving, b * (1.0 - 1.0 / _MARGIN), b))
                with np.errstate(divide="ignore", invalid="ignore"):
                    speed = np.where(moving, b / (_MARGIN * np.where(moving, t[:, None], 1.0)), np.inf)
                k_stat = np.maximum(k_stat, np.where(b > 0.0, _inverse_group_velocity(speed, p.d, p.g), np.inf))
            else:
                slope_lo = np.minimum(slope_lo, np.abs(b - c0 * t[:, None]))
        # remainder of the two-term tail, per level: 9 |C(K)| / (K^2 theta'^3) <= tol * amplitude
        kern = _kernel_amplitudes(ladder[:, None], r[None, :], p.geometry)
        size = (np.abs(edge.amplitude(ladder))[:, None] * np.maximum(np.abs(kern[0]), np.abs(kern[1]))
                * _measure(ladder, p.geometry)[:, None])
        remainder = 9.0 * size / ladder[:, None] ** 2 / (tol * p.shape.amplitude / len(edges))
        need_rem = np.sum(remainder[:, None, :] > slope_lo[None] ** 3, axis=0)
        need_stat = np.searchsorted(ladder, k_stat, side="left")
        level = np.maximum(level, np.maximum(need_rem, need_stat))
    return np.minimum(level, n_levels - 1), level < n_levels


def _nodes(cutoff, reach, t_max, p: _Problem, refine):
    """Gauss-Legendre nodes and weights on [0, cutoff]: panels advancing the phase
    reach k + omega(k) t_max by at most 3 pi / refine and, with dispersion, no
    wider than (1 + k d/4)/d (1/d where tanh(kd) varies, k/4 where omega ~ sqrt(g k))."""
    phase = _PANEL_PHASE / refine

    def advance(k):  # phase plus the panel-width limit, in units where one panel advances by ``phase``
        width = 4.0 * np.log1p(0.25 * k * p.d) * refine if p.dispersive else 0.0
        return reach * k + _omega(k, p.d, p.g, p.dispersive) * t_max + phase * width

    total = float(advance(np.float64(cutoff)))
    n_panels = max(1, math.ceil(total / phase))
    k_tab = np.linspace(0.0, cutoff, 4 * n_panels + 65)
    p_tab = advance(k_tab)
    ends = np.interp(np.linspace(0.0, total, n_panels + 1), p_tab, k_tab)
    ends[0], ends[-1] = 0.0, cutoff
    mid, half = 0.5 * (ends[1:] + ends[:-1]), 0.5 * (ends[1:] - ends[:-1])
    return (mid[:, None] + half[:, None] * _GL_X).ravel(), (half[:, None] * _GL_W).ravel()


def _body(p: _Problem, r, t, k, w, pairs):
    """int_0^K of the eta and u integrands, on the grid r x t, or on the (r, t) pairs if ``pairs``."""
    weight = w * p.shape.transform(k, p.geometry) * _measure(k, p.geometry)
    omega = _omega(k, p.d, p.g, p.dispersive)
    speed = omega / (k * p.d)
    if pairs:
        eta, u = np.zeros(r.size), np.zeros(r.size)
    else:
        eta, u = np.zeros((t.size, r.size)), np.zeros((t.size, r.size))
    step = max(64, _CHUNK // max(r.size, t.size))
    for lo in range(0, k.size, step):
        sl = slice(lo, lo + step)
        kern_eta, kern_u = _kernels(k[None, sl], r[:, None], p.geometry)
        phase = omega[None, sl] * t[:, None]
        if pairs:
            eta += (kern_eta * np.cos(phase)) @ weight[sl]
            u += (kern_u * np.sin(phase)) @ (weight[sl] * speed[sl])
        else:
            eta += (np.cos(phase) * weight[sl]) @ kern_eta.T
            u += (np.sin(phase) * (weight[sl] * speed[sl])) @ kern_u.T
    return eta, u


def _tail(p: _Problem, r, t, cutoff):
    """int_K^inf of the eta and u integrands at the (r, t) pairs, by two integrations by parts."""
    eta, u = np.zeros(r.size), np.zeros(r.size)
    k = cutoff * np.array([1.0 - _DELTA, 1.0, 1.0 + _DELTA])[:, None]
    omega = _omega(k, p.d, p.g, p.dispersive)
    c_g = _group_velocity(k, p.d, p.g, p.dispersive)
    common = _measure(k, p.geometry)
    speed = omega / (k * p.d)
    kern_eta, kern_u = _kernel_amplitudes(k, r[None, :], p.geometry)
    for edge in p.shape.edges(p.geometry):
        a = edge.amplitude(k) * common
        for s_x in (1.0, -1.0):
            for s_t in (1.0, -1.0):
                slope = edge.position + s_x * r + s_t * c_g * t
                theta = cutoff * (edge.position + s_x * r) + s_t * omega[1] * t
                turn = np.exp(1j * theta)
                for out, kern, time_coef, factor in ((eta, kern_eta, 1.0, 1.0), (u, kern_u, -1j, speed)):
                    c = (a * factor * (kern if s_x > 0 else np.conj(kern))
                         * (time_coef if s_t > 0 else np.conj(time_coef)))
                    with np.errstate(divide="ignore", invalid="ignore"):
                        phi = c / (1j * slope)
                        d_phi = (phi[2] - phi[0]) / (2.0 * _DELTA * cutoff)
                        value = -turn * (phi[1] - d_phi / (1j * slope[1]))
                    out += 0.25 * np.where(np.isfinite(value), value, 0.0).real
    return eta, u


def linear_wave_fields(shape: InitialShape, x, times, d, *, geometry: str = "planar", g: float = GRAVITY,
                       dispersive: bool = True, tol: float = 1e-7, k_max: float | None = None,
                       refine: float = 1.0, return_resolved: bool = False):
    """Free-surface elevation eta and depth-averaged velocity u of linear waves from ``shape`` at rest.

    eta(x, t) = (1/pi) int_0^inf F(k) cos(kx) cos(omega t) dk and
    u = (1/pi) int_0^inf F(k) sin(kx) (omega/(kd)) sin(omega t) dk (planar,
    eta0 even in x; u is odd) or eta(r, t) = int_0^inf G(k) J0(kr) cos(omega t) k dk,
    u = int_0^inf G(k) J1(kr) (omega/(kd)) sin(omega t) k dk (radial),
    omega^2 = g k tanh(k d), or omega = k sqrt(g d) if not ``dispersive``
    (Whitham 1974, §13; Mei 1989, ch. 2). Quadrature and error bound: see the
    module docstring.

    ``x``: positions [m] (any order; r >= 0 in radial geometry); ``times``:
    times [s] >= 0; ``d`` > 0 the still depth [m]. ``tol`` (in (0, 1e-3])
    is the truncation target per edge relative to max|eta0|; ``k_max`` the
    largest cut-off [rad/m] (default 2^17 / shape.length); ``refine`` (in
    [1, 16]) multiplies the node density and every cut-off, for
    convergence checks. Returns ``(eta, u)`` of shape (len(times), len(x)),
    and with ``return_resolved`` also a boolean array that is False where
    the cut-off needed exceeds ``k_max`` (the Gibbs bands at edges).
    """
    if not isinstance(shape, InitialShape):
        raise ValueError(  # noqa: TRY004 - every bad input is a ValueError (SPEC §9)
            f"shape must be an InitialShape such as Mound, Crater or Gaussian, got {shape!r}.")
    geometry = checked_geometry(geometry)
    d, g = positive("d", d), positive("g", g)
    tol = in_range("tol", tol, 0.0, 1e-3, lo_open=True)
    refine = in_range("refine", refine, 1.0, 16.0)
    x = np.atleast_1d(np.asarray(x, dtype=float))
    if x.ndim != 1 or x.size == 0 or not np.all(np.isfinite(x)):
        raise ValueError("x must be a non-empty, finite 1D array of positions.")
    if geometry == "radial" and np.any(x < 0.0):
        raise ValueError("x must be >= 0 in radial geometry (it is the distance r from the axis).")
    t = np.atleast_1d(np.asarray(times, dtype=float))
    if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)) or np.any(t < 0.0):
        raise ValueError("times must be a non-empty, finite 1D array of values >= 0.")
    k_lo = max(4.0 / shape.length, shape.k_smooth)
    k_max = 2.0**17 / shape.length if k_max is None else positive("k_max", k_max)
    if k_max < k_lo:
        raise ValueError(f"k_max must be at least {k_lo:g} rad/m for this shape, got {k_max:g}.")
    p = _Problem(shape, geometry, d, g, bool(dispersive))
    r = np.abs(x)
    ladder = k_lo * 2.0 ** np.arange(math.floor(math.log2(k_max / k_lo)) + 1)
    level, resolved = _levels(p, r, t, ladder, tol)
    reach = max((e.position for e in shape.edges(geometry)), default=shape.length)
    eta, u = np.zeros((t.size, r.size)), np.zeros((t.size, r.size))
    for lv in np.unique(level):
        it, ix = np.nonzero(level == lv)
        cols, rows = np.unique(ix), np.unique(it)
        cutoff = refine * ladder[lv]
        k, w = _nodes(cutoff, reach + r[cols].max(), t[rows].max(), p, refine)
        if 20 * (cols.size + rows.size) + cols.size * rows.size <= 40 * it.size:
            block_eta, block_u = _body(p, r[cols], t[rows], k, w, pairs=False)
            pos_t, pos_x = np.searchsorted(rows, it), np.searchsorted(cols, ix)
            eta[it, ix], u[it, ix] = block_eta[pos_t, pos_x], block_u[pos_t, pos_x]
        else:
            eta[it, ix], u[it, ix] = _body(p, r[ix], t[it], k, w, pairs=True)
        tail_eta, tail_u = _tail(p, r[ix], t[it], cutoff)
        eta[it, ix] += tail_eta
        u[it, ix] += tail_u
    if geometry == "planar":
        u *= np.sign(x)
    return (eta, u, resolved) if return_resolved else (eta, u)


def linear_waves(shape: InitialShape, x, times, d, geometry: str = "planar", g: float = GRAVITY,
                 dispersive: bool = True, case: str | None = None, **quadrature) -> xr.Dataset:
    """Linear waves from ``shape`` at rest in still depth ``d`` as a partmesh result Dataset.

    Fields on (time, x) from :func:`linear_wave_fields` (Whitham 1974, §13;
    Mei 1989): ``eta`` the free-surface elevation above still water, ``u``
    the depth-averaged velocity of linear theory (x velocity in planar
    geometry, radial velocity in radial geometry, where the ``x``
    coordinate holds the distance r from the axis) and ``h = d + eta``.
    ``x`` strictly increasing (>= 0 radial); ``times`` increasing, >= 0.
    ``quadrature`` passes ``tol``, ``k_max`` and ``refine`` on. ``case``
    defaults to the shape's name.
    """
    geometry = checked_geometry(geometry)
    x = axis("x", x)
    times = output_times(times)
    eta, u = linear_wave_fields(shape, x, times, d, geometry=geometry, g=g, dispersive=dispersive, **quadrature)
    d, g = float(d), float(g)
    dispersion_text = "omega^2 = g k tanh(k d)" if dispersive else "omega = k sqrt(g d)"
    transform = "Fourier cosine" if geometry == "planar" else "Hankel"
    long_names = {"u": f"depth-averaged {'x' if geometry == 'planar' else 'radial'} velocity (linear theory)"}
    if geometry == "radial":
        long_names["x"] = "distance r from the axis of symmetry"
    return result(
        case=case or shape.name, method="exact",
        scheme=f"linear waves from rest, {transform} integral, {dispersion_text} (Whitham 1974 §13)",
        x=x, times=times, dx=float(np.mean(np.diff(x))),
        fields={"eta": eta, "u": u, "h": d + eta},
        parameters={**shape.parameters(), "d": d, "g": g, "geometry": geometry, "dispersive": bool(dispersive),
                    **{key: value for key, value in quadrature.items() if value is not None}},
        long_names=long_names,
    )


def standing_wave_fields(x, times, amplitude, k, d, g: float = GRAVITY, dispersive: bool = True):
    """``(eta, u)`` (time, x) of the linear standing wave η = a cos(kx) cos(ωt)
    from rest (Lamb 1932 §228), ω from :func:`dispersion`; u is the
    depth-averaged velocity continuity gives, ∂η/∂t + d ∂u/∂x = 0:
    u = (a ω/(k d)) sin(kx) sin(ωt)."""
    x, t = np.asarray(x, float), np.asarray(times, float)[:, None]
    omega = float(dispersion(k, d, g, dispersive))
    eta = amplitude * np.cos(k * x) * np.cos(omega * t)
    u = amplitude * omega / (k * d) * np.sin(k * x) * np.sin(omega * t)
    return eta, u


def standing_wave(x, times, amplitude, k, d, g: float = GRAVITY, dispersive: bool = True,
                  case: str = "standing_wave") -> xr.Dataset:
    """:func:`standing_wave_fields` as a partmesh result Dataset (``eta``, ``u``, ``h = d + eta``)."""
    x, times = axis("x", x), output_times(times)
    eta, u = standing_wave_fields(x, times, amplitude, k, d, g, dispersive)
    dispersion_text = "omega^2 = g k tanh(k d)" if dispersive else "omega = k sqrt(g d)"
    return result(
        case=case, method="exact", scheme=f"linear standing wave, {dispersion_text} (Lamb 1932 §228)",
        x=x, times=times, dx=float(np.mean(np.diff(x))), fields={"eta": eta, "u": u, "h": d + eta},
        parameters={"amplitude": float(amplitude), "k": float(k), "d": float(d), "g": float(g),
                    "dispersive": bool(dispersive)},
        long_names={"u": "depth-averaged x velocity (linear theory)"},
    )
