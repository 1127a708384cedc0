"""Pullin's Equilibrium Flux Method (partmesh.gridref.euler.riemann.efm): its
half-range fluxes against direct quadrature of the Maxwellian, consistency
with the physical flux, upwinding of supersonic states, and sod."""

import numpy as np
import pytest
from scipy import integrate

from partmesh.gridref.euler.riemann import efm, half_range_flux
from partmesh.gridref.euler.state import normal_flux

GAMMA = 1.4


def _quadrature(rho, un, vt, p, gamma, sign):
    """Half-range moments by quadrature over the normal velocity c of the
    Maxwellian ρ/√(2πθ) exp(−(c − u_n)²/(2θ)): the molecules with sign·c > 0
    carry mass c, normal momentum c², tangential momentum c u_t and energy
    c (½c² + ½u_t² + θ/2·(tangential degrees) + internal), the last two
    summing to e − θ/2 per mass with e = p/((γ − 1)ρ)."""
    theta = p / rho
    e_rest = p / ((gamma - 1.0) * rho) - 0.5 * theta + 0.5 * vt * vt

    def g(c):
        return rho / np.sqrt(2 * np.pi * theta) * np.exp(-(c - un) ** 2 / (2 * theta))

    lo, hi = (0.0, un + 40 * np.sqrt(theta)) if sign > 0 else (un - 40 * np.sqrt(theta), 0.0)
    moments = [integrate.quad(lambda c, k=k: c**k * g(c), lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
               for k in (1, 2, 3)]
    return moments[0], moments[1], vt * moments[0], 0.5 * moments[2] + e_rest * moments[0]


@pytest.mark.parametrize("state", [(1.0, 0.3, -0.2, 1.0), (0.125, -1.7, 0.5, 0.1), (2.0, 4.0, 0.0, 0.5)])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_half_range_fluxes_equal_the_maxwellian_moments(state, sign):
    rho, un, vt, p = state
    got = half_range_flux(tuple(np.array(q) for q in state), GAMMA, sign)
    want = _quadrature(rho, un, vt, p, GAMMA, sign)
    np.testing.assert_allclose(np.array(got, dtype=float), want, rtol=1e-10, atol=1e-12)


def test_efm_of_equal_states_is_the_physical_flux():
    rng = np.random.default_rng(4)
    W = (rng.uniform(0.1, 2, 50), rng.normal(0, 2, 50), rng.normal(0, 1, 50), rng.uniform(0.1, 3, 50))
    np.testing.assert_allclose(np.array(efm(W, W, GAMMA)), np.array(normal_flux(W, GAMMA)), rtol=1e-12, atol=1e-12)


def test_efm_takes_the_upwind_flux_of_hypersonic_states():
    # s = u/√(2θ) = 10: the other side's molecules cannot reach the face (e^{-100})
    WL = (np.array(1.0), np.array(10.0 * np.sqrt(2.0)), np.array(0.3), np.array(1.0))
    WR = (np.array(0.5), np.array(10.0 * np.sqrt(2.0 * 0.4)), np.array(-0.1), np.array(0.2))
    np.testing.assert_allclose(np.array(efm(WL, WR, GAMMA)), np.array(normal_flux(WL, GAMMA)), rtol=1e-14)
