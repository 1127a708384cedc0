"""The planar CJ detonation and its Taylor wave (partmesh.compare.exact.detonation): the ideal-gas closed
form, the CJ state at the front, the rest state, and the self-similar Euler equations inside the wave."""

import numpy as np
import pytest

from partmesh.compare.exact import taylor_wave
from partmesh.compare.materials import JWL, TNT


@pytest.mark.parametrize("gamma", [1.4, 3.0])
def test_an_ideal_gas_detonation_is_the_closed_form(gamma):
    """Products of γ with energy e₀: D² = 2(γ² − 1) e₀ (the strong-detonation CJ speed), and behind it
    u = 2(ξ − D/2)/(γ + 1), c = D/2 + (γ − 1) u/2, at rest for ξ ≤ D/2."""
    gas = JWL("ideal", A=1e-300, B=1e-300, R1=4.15, R2=0.95, omega=gamma - 1.0, rho0=1.0, e0=4e6, c_reactant=1.0)
    wave = taylor_wave(gas)
    D = np.sqrt(2.0 * (gamma**2 - 1.0) * gas.e0)
    assert wave.D == pytest.approx(D, rel=1e-9)
    assert wave.rest == pytest.approx(D / 2.0, rel=1e-7)
    xi = np.linspace(0.05, 0.999, 40) * D
    rho, u, p, e = wave.at(xi)
    u_exact = np.where(xi > D / 2.0, 2.0 * (xi - D / 2.0) / (gamma + 1.0), 0.0)
    np.testing.assert_allclose(u, u_exact, rtol=1e-7, atol=1e-7 * D)
    np.testing.assert_allclose(gas.sound_speed(rho, e), D / 2.0 + (gamma - 1.0) * u_exact / 2.0, rtol=1e-7)


def test_the_front_carries_the_cj_state_and_the_wall_side_rests():
    wave = taylor_wave(TNT)
    cj = TNT.cj_state()
    rho, u, p, _ = wave.at(np.array([cj.D * (1 - 1e-12), 0.5 * wave.rest, wave.rest, 1.01 * cj.D]))
    assert rho[0] == pytest.approx(cj.rho, rel=1e-6) and u[0] == pytest.approx(cj.u, rel=1e-6)
    assert p[0] == pytest.approx(cj.p, rel=1e-6)
    assert u[1] == u[2] == 0.0 and rho[1] == rho[2] == wave.rho_rest and p[1] == wave.p_rest
    assert (rho[3], u[3], p[3]) == (TNT.rho0, 0.0, 0.0)
    assert 0.0 < wave.rest < cj.D and 0.0 < wave.p_rest < cj.p


def test_the_wave_solves_the_self_similar_euler_equations():
    """For ρ(ξ), u(ξ), p(ξ): (u − ξ) ρ' + ρ u' = 0 and (u − ξ) u' + p'/ρ = 0, by central differences of the
    sampled profile inside the wave, to 1e-5 of the terms' size."""
    wave = taylor_wave(TNT)
    xi = np.linspace(wave.rest, wave.D, 402)[1:-1]
    h = 1e-4 * (wave.D - wave.rest)
    (rho_m, u_m, p_m, _), (rho, u, p, _), (rho_p, u_p, p_p, _) = (wave.at(xi + s) for s in (-h, 0.0, h))
    d_rho, d_u, d_p = (rho_p - rho_m) / (2 * h), (u_p - u_m) / (2 * h), (p_p - p_m) / (2 * h)
    mass = (u - xi) * d_rho + rho * d_u
    momentum = (u - xi) * d_u + d_p / rho
    assert np.max(np.abs(mass) / (np.abs(rho * d_u))) < 1e-5
    assert np.max(np.abs(momentum) / np.abs(d_p / rho)) < 1e-5
