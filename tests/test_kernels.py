"""SPH kernels (partmesh.particle.kernels): normalisation, derivatives, support,
shape, the derived 1D constants, the h ↔ H conversions and the skewed
kernel of SPEC §3.1."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numba
import numpy as np
import pytest
from scipy.integrate import quad

from partmesh.cases.errors import InputError
from partmesh.particle import kernels as K

NAMES = list(K.KERNELS)
BREAKS = {"cubic_spline": [0.5], "quintic_spline": [1 / 3, 2 / 3]}  # in q = r/H


def _quad(fun, a, b, points=()):
    pts = [p for p in points if a < p < b]
    val, _err = quad(fun, a, b, points=pts or None, epsabs=1e-14, epsrel=1e-13, limit=400)
    return val


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("H", [0.7, 2.3])
def test_normalisation(name, H):
    brk = [b * H for b in BREAKS.get(name, [])]
    i1 = 2.0 * _quad(lambda r: K.w(name, r, H, 1), 0.0, H, brk)
    i2 = _quad(lambda r: 2.0 * math.pi * r * K.w(name, r, H, 2), 0.0, H, brk)
    i3 = _quad(lambda r: 4.0 * math.pi * r * r * K.w(name, r, H, 3), 0.0, H, brk)
    assert i1 == pytest.approx(1.0, abs=1e-10)
    assert i2 == pytest.approx(1.0, abs=1e-10)
    assert i3 == pytest.approx(1.0, abs=1e-10)


def _poly_int_exact(n, coeffs):
    """∫_0^1 (1−q)^n Σ c_k q^k dq, exactly, by the Beta integral k! n!/(n+k+1)!."""
    return sum(
        Fraction(c) * Fraction(math.factorial(k) * math.factorial(n), math.factorial(n + k + 1))
        for k, c in enumerate(coeffs)
    )


@pytest.mark.parametrize(
    "name, n, coeffs, sigma1",
    [
        ("wendland_c6", 8, [1, 8, 25, 32], Fraction(15, 8)),
        ("wendland_c4", 6, [1, 6, Fraction(35, 3)], Fraction(27, 16)),
        ("wendland_c2", 4, [1, 4], Fraction(3, 2)),
    ],
)
def test_wendland_1d_sigma_is_the_derived_rational(name, n, coeffs, sigma1):
    assert 1 / (2 * _poly_int_exact(n, coeffs)) == sigma1
    assert K.sigma(name, 1) == float(sigma1)
    assert K.w(name, 0.0, 1.0, 1) == float(sigma1)


def test_wendland_c6_2d_normalisation_of_the_spec():
    H = 0.37
    nf = 78.0 / (7.0 * math.pi * H * H)
    r = np.linspace(0.0, H, 50, endpoint=False)
    R = r / H
    expected = nf * (1 - R) ** 8 * (1 + 8 * R + 25 * R**2 + 32 * R**3)
    np.testing.assert_allclose(K.w("wendland_c6", r, H, 2), expected, rtol=1e-14, atol=0)
    # and the SPEC's n_f is right: 2π ∫ R f(R) dR = 7π/78
    I1 = _poly_int_exact(8, [0, 1, 8, 25, 32])
    assert 2 * I1 == Fraction(7, 78)


def test_splines_and_gaussian_match_their_h_forms():
    h = 0.41
    s = np.linspace(0.0, 3.0, 301)[:-1]
    r = s * h

    def m4(s):
        return np.where(s < 1, 1 - 1.5 * s**2 + 0.75 * s**3, np.where(s < 2, 0.25 * (2 - s) ** 3, 0.0))

    def m6(s):
        t = lambda a: np.clip(a - s, 0, None) ** 5
        return t(3) - 6 * t(2) + 15 * t(1)

    H2 = 2 * h
    np.testing.assert_allclose(K.w("cubic_spline", r, H2, 1), 2 / (3 * h) * m4(s), rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(K.w("cubic_spline", r, H2, 2), 10 / (7 * np.pi * h**2) * m4(s), rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(K.w("cubic_spline", r, H2, 3), 1 / (np.pi * h**3) * m4(s), rtol=1e-13, atol=1e-15)
    H3 = 3 * h
    np.testing.assert_allclose(K.w("quintic_spline", r, H3, 1), m6(s) / (120 * h), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(K.w("quintic_spline", r, H3, 2), 7 * m6(s) / (478 * np.pi * h**2), rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(K.w("quintic_spline", r, H3, 3), m6(s) / (120 * np.pi * h**3), rtol=1e-12, atol=1e-15)
    # truncated Gaussian: exp(−(r/h)²)/(π h²) renormalised for the cut at 3h
    np.testing.assert_allclose(
        K.w("gaussian", r, H3, 2), np.exp(-(s**2)) / (np.pi * h**2) / (1 - np.exp(-9.0)), rtol=1e-13
    )
    # the Wendland C2 of SPEC §3.2: α_D (1 − q/2)^4 (2q + 1), α_D = 7/(4πh²), q = r/h ≤ 2
    q = s[s < 2]
    np.testing.assert_allclose(
        K.w("wendland_c2", q * h, 2 * h, 2), 7 / (4 * np.pi * h**2) * (1 - q / 2) ** 4 * (2 * q + 1), rtol=1e-13, atol=1e-15
    )
    assert [K.support_ratio(n) for n in NAMES] == [2.0, 2.0, 2.0, 2.0, 3.0, 3.0]


def _sample_q(name, n=400):
    q = np.linspace(0.01, 0.99, n)
    for b in BREAKS.get(name, []):
        q = q[np.abs(q - b) > 1e-3]
    return q


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("dim", [1, 2, 3])
def test_derivatives_against_finite_differences(name, dim):
    H = 0.83
    r = _sample_q(name) * H
    eps = 1e-5 * H
    num_r = (K.w(name, r + eps, H, dim) - K.w(name, r - eps, H, dim)) / (2 * eps)
    num_h = (K.w(name, r, H + eps, dim) - K.w(name, r, H - eps, dim)) / (2 * eps)
    ana_r = K.dwdr(name, r, H, dim)
    ana_h = K.dwdh(name, r, H, dim)
    for num, ana in ((num_r, ana_r), (num_h, ana_h)):
        scale = np.abs(ana).max()
        np.testing.assert_allclose(num, ana, rtol=1e-6, atol=1e-9 * scale)


@pytest.mark.parametrize("name", NAMES)
def test_dwdh_identity_and_eval(name):
    """∂W/∂H = −(d W + r ∂W/∂r)/H, and kernel_eval returns the three at once."""
    kind = K.KERNELS[name]
    H = 1.3
    for dim in (1, 2, 3):
        for r in (0.0, 0.1, 0.5, 0.77, 1.2):
            wv, dr, dh = K.kernel_eval(kind, r, H, dim)
            assert wv == K.kernel_w(kind, r, H, dim)
            assert dr == pytest.approx(K.kernel_dwdr(kind, r, H, dim), rel=1e-14, abs=1e-300)
            assert dh == pytest.approx(K.kernel_dwdh(kind, r, H, dim), rel=1e-14, abs=1e-300)
            assert dh == pytest.approx(-(dim * wv + r * dr) / H, rel=1e-12, abs=1e-14)


@pytest.mark.parametrize("name", NAMES)
def test_compact_support_positive_and_monotone(name):
    H = 0.6
    for dim in (1, 2, 3):
        out = np.array([H, H * (1 + 1e-15), 1.0001 * H, 2 * H, 1e6])
        assert np.all(K.w(name, out, H, dim) == 0.0)
        assert np.all(K.dwdr(name, out, H, dim) == 0.0)
        assert np.all(K.dwdh(name, out, H, dim) == 0.0)
        r = np.linspace(0.0, H, 20001)[:-1]
        wv = K.w(name, r, H, dim)
        assert np.all(wv > 0.0)
        assert np.all(np.diff(wv) <= 1e-14 * wv[0])
        assert np.all(K.dwdr(name, r, H, dim) <= 0.0)
    # dW/dr vanishes at the centre (smooth kernels)
    assert K.dwdr(name, 0.0, H, 2) == 0.0


def test_vectorised_wrappers_broadcast_and_match_scalars():
    r = np.linspace(0, 1.5, 7)[:, None]
    H = np.array([0.5, 1.0, 2.0])
    out = K.w("wendland_c4", r, H, 2)
    assert out.shape == (7, 3)
    for a in range(7):
        for b in range(3):
            assert out[a, b] == K.kernel_w(K.KERNELS["wendland_c4"], r[a, 0], H[b], 2)
    assert isinstance(K.w("cubic_spline", 0.3, 1.0, 1), float)


def test_scalar_kernels_callable_from_numba():
    kind = K.KERNELS["wendland_c6"]

    @numba.njit
    def density(x, m, H):
        n = x.size
        rho = np.zeros(n)
        for i in range(n):
            for j in range(n):
                rho[i] += m * K.kernel_w(kind, abs(x[i] - x[j]), H, 1)
        return rho

    dx = 0.01
    x = np.arange(0.0, 1.0, dx)
    rho = density(x, dx, 4 * dx)
    assert rho[50] == pytest.approx(1.0, rel=1e-3)


def test_bad_input_is_refused():
    with pytest.raises(InputError, match="kernel"):
        K.w("wendland_c8", 0.1, 1.0, 2)
    with pytest.raises(InputError, match="dim"):
        K.w("wendland_c6", 0.1, 1.0, 4)
    with pytest.raises(InputError, match="H"):
        K.w("wendland_c6", 0.1, 0.0, 2)
    with pytest.raises(InputError, match="H"):
        K.dwdr("wendland_c6", 0.1, np.nan, 2)
    with pytest.raises(InputError, match="r"):
        K.dwdh("wendland_c6", -0.1, 1.0, 2)
    with pytest.raises(InputError, match="kernel"):
        K.support_ratio("spline")
    with pytest.raises(ValueError):  # InputError is a ValueError
        K.w("gaussian", [0.1, 0.2], [1.0, 1.0, 1.0], 1)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("dim", [1, 2])
def test_least_eta_is_where_the_density_solve_gains_a_solution(name, dim):
    """On the unit square lattice (unit masses, ρ = 1) the joint solve
    Σ_j W(r_ij, H) = (η/H)^d has no root H for η at least_eta and a root
    just above it: a brute-force scan of H over the lattice's own sums."""
    least = K.least_eta(name, dim)
    offsets = np.arange(-12, 13)
    r = (np.abs(offsets) if dim == 1 else
         np.hypot(*np.meshgrid(offsets, offsets)).ravel())
    H = np.geomspace(0.05, 10.0, 4000)
    sums = np.array([K.w(name, r, h, dim).sum() for h in H])
    assert np.all(sums - (least / H) ** dim > -1e-12 * sums)
    assert np.any(sums - (1.02 * least / H) ** dim < 0.0)


# ---------------------------------------------------------------------------
# skewed kernel (SPEC §3.1)
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["wendland_c6", "cubic_spline", "gaussian"])
def test_skewed_kernel_symmetry_and_cutoff(name):
    kind = K.KERNELS[name]
    H = 0.9
    c = 10.0
    n_hat = np.array([np.cos(0.4), np.sin(0.4)])  # wall normal into the fluid
    lam = -c * n_hat
    rng = np.random.default_rng(3)
    for rx, ry in rng.uniform(-H, H, (200, 2)):
        ws_p = K.skewed_w(kind, rx, ry, H, 2, lam[0], lam[1])
        ws_m = K.skewed_w(kind, -rx, -ry, H, 2, lam[0], lam[1])
        w0 = K.kernel_w(kind, math.hypot(rx, ry), H, 2)
        assert ws_p + ws_m == pytest.approx(2.0 * w0, rel=1e-12, abs=1e-300)
        assert 0.0 <= ws_p <= 2.0 * w0 * (1 + 1e-14)
    # λ·R ≪ 0 (r_vec = x_i − x_j along −λ): switched off; λ·R ≫ 0: weight 2W
    r_vec = 0.5 * H * n_hat  # λ·R = −5
    w0 = K.kernel_w(kind, 0.5 * H, H, 2)
    assert K.skewed_w(kind, r_vec[0], r_vec[1], H, 2, lam[0], lam[1]) < 1e-11 * w0
    assert K.skewed_w(kind, -r_vec[0], -r_vec[1], H, 2, lam[0], lam[1]) == pytest.approx(2 * w0, rel=1e-11)


@pytest.mark.parametrize("name", ["wendland_c6", "wendland_c2", "quintic_spline"])
def test_skewed_kernel_integrates_to_one(name):
    kind = K.KERNELS[name]
    H = 1.1
    # 1D
    for lam in (-10.0, 3.0):
        val = _quad(lambda x, lam=lam: K.skewed_w(kind, x, 0.0, H, 1, lam, 0.0), -H, H, [0.0] + [
            s * b * H for b in BREAKS.get(name, []) for s in (-1, 1)])
        assert val == pytest.approx(1.0, abs=1e-10)
    # 2D: Gauss–Legendre in r (per kernel piece) × trapezoid in θ (periodic, so
    # spectrally accurate; an odd count so no node has its opposite θ + π)
    lam = -10.0 * np.array([np.cos(0.3), np.sin(0.3)])
    edges = [0.0] + [b * H for b in BREAKS.get(name, [])] + [H]
    xr, wr = np.polynomial.legendre.leggauss(40)
    nt = 801
    theta = 1.0 + 2.0 * np.pi * np.arange(nt) / nt
    wt = np.full(nt, 2.0 / nt)
    skew = np.vectorize(K.skewed_w, otypes=[float])
    total = 0.0
    for a, b in itertools.pairwise(edges):
        r = a + (b - a) * (xr + 1) / 2
        R, T = np.meshgrid(r, theta, indexing="ij")
        vals = skew(kind, R * np.cos(T), R * np.sin(T), H, 2, lam[0], lam[1])
        total += np.einsum("i,j,ij->", wr * (b - a) / 2 * r, wt * np.pi, vals)
    assert total == pytest.approx(1.0, abs=1e-10)


def test_skewed_gradient_against_finite_differences():
    kind = K.KERNELS["wendland_c6"]
    H = 0.8
    lam = (-7.0, 4.0)
    eps = 1e-6
    rng = np.random.default_rng(5)
    for rx, ry in rng.uniform(-0.55, 0.55, (50, 2)):
        gx, gy = K.skewed_grad(kind, rx, ry, H, 2, *lam)
        fx = (K.skewed_w(kind, rx + eps, ry, H, 2, *lam) - K.skewed_w(kind, rx - eps, ry, H, 2, *lam)) / (2 * eps)
        fy = (K.skewed_w(kind, rx, ry + eps, H, 2, *lam) - K.skewed_w(kind, rx, ry - eps, H, 2, *lam)) / (2 * eps)
        scale = abs(K.kernel_dwdr(kind, 0.3 * H, H, 2)) * 2
        assert gx == pytest.approx(fx, rel=1e-6, abs=1e-8 * scale)
        assert gy == pytest.approx(fy, rel=1e-6, abs=1e-8 * scale)
    assert K.skewed_grad(kind, H, 0.0, H, 2, *lam) == (0.0, 0.0)
