"""The JWL equation of state (partmesh.compare.materials) against its closed forms, an independent
integration of the isentrope, the ideal-gas limit, and TNT's published Chapman–Jouguet state."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from partmesh.compare.checks import InputError
from partmesh.compare.materials import JWL, TNT

RHO = np.linspace(0.05, 2.4, 60) * TNT.rho0  # from far expanded products to beyond the CJ density


def test_the_pressure_on_a_closed_form_isentrope_is_the_isentropes():
    """p(ρ, e_s(ρ)) = p_s(ρ): the general equation of state and the closed-form isentrope agree (the
    exponential terms' ω parts cancel against e_s's), for the principal isentrope and two others."""
    cj = TNT.cj_state()
    for C in (TNT.isentrope(cj.rho, cj.p), 0.5e9, 2.0e9):
        np.testing.assert_allclose(TNT.pressure(RHO, TNT.isentrope_energy(RHO, C)), TNT.isentrope_pressure(RHO, C),
                                   rtol=1e-12)


def test_the_isentrope_integrated_from_the_cj_state_is_the_closed_form():
    """de/dρ = p(ρ, e)/ρ² (no heat: de = −p dv), integrated with the general p from the CJ state down to a
    twentieth of the unreacted density, meets e_s and p_s of the isentrope through the CJ point."""
    cj = TNT.cj_state()
    C = TNT.isentrope(cj.rho, cj.p)
    rho = np.geomspace(cj.rho, 0.05 * TNT.rho0, 40)
    path = solve_ivp(lambda r, e: TNT.pressure(r, e) / r**2, (rho[0], rho[-1]), [cj.e], t_eval=rho,
                     rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(path.y[0], TNT.isentrope_energy(rho, C), rtol=1e-9)
    np.testing.assert_allclose(TNT.pressure(rho, path.y[0]), TNT.isentrope_pressure(rho, C), rtol=1e-8)


def test_the_sound_speed_is_the_slope_of_the_isentrope():
    """c² = dp_s/dρ along an isentrope: the closed-form sound speed against a central difference of p_s."""
    cj = TNT.cj_state()
    C = TNT.isentrope(cj.rho, cj.p)
    h = 1e-5 * RHO
    slope = (TNT.isentrope_pressure(RHO + h, C) - TNT.isentrope_pressure(RHO - h, C)) / (2 * h)
    np.testing.assert_allclose(TNT.sound_speed(RHO, TNT.isentrope_energy(RHO, C)) ** 2, slope, rtol=1e-7)


def test_without_its_exponential_terms_the_products_are_an_ideal_gas_of_gamma_one_plus_omega():
    gas = JWL("weak", A=1e-300, B=1e-300, R1=4.15, R2=0.95, omega=0.4, rho0=1.0, e0=2.5e5, c_reactant=1.0)
    rho, e = np.array([0.1, 1.0, 3.0]), np.array([1e5, 2.5e5, 7e5])
    p = gas.pressure(rho, e)
    np.testing.assert_allclose(p, 0.4 * rho * e, rtol=1e-14)
    np.testing.assert_allclose(gas.sound_speed(rho, e), np.sqrt(1.4 * p / rho), rtol=1e-14)


def test_tnts_cj_state_is_the_handbooks_within_one_percent():
    """Dobratz & Crawford (1985): D 6 930 m/s, p_CJ 21.0 GPa; the density on their Rayleigh line,
    ρ₀ D²/(ρ₀ D² − p), 2 227.6 kg/m³. Measured: 6 929.4 m/s, 21.00 GPa, 2 227.7 kg/m³."""
    cj = TNT.cj_state()
    rho_handbook = TNT.rho0 * TNT.rho0 * 6930.0**2 / (TNT.rho0 * 6930.0**2 - 21.0e9)
    assert cj.D == pytest.approx(6930.0, rel=0.01)
    assert cj.p == pytest.approx(21.0e9, rel=0.01)
    assert cj.rho == pytest.approx(rho_handbook, rel=0.01)


def test_the_cj_state_is_sonic_on_the_hugoniot_and_the_rayleigh_line():
    """At the CJ point the products leave at the speed of sound relative to the front (u + c = D), the state
    is on the Hugoniot (ρ₀(e − e₀) = ½ p (1 − V)) and on the Rayleigh line (p = ρ₀ D u), and the
    equation of state gives its pressure."""
    cj = TNT.cj_state()
    V = TNT.rho0 / cj.rho
    assert cj.u + float(TNT.sound_speed(cj.rho, cj.e)) == pytest.approx(cj.D, rel=1e-6)
    assert TNT.rho0 * (cj.e - TNT.e0) == pytest.approx(0.5 * cj.p * (1.0 - V), rel=1e-12)
    assert cj.p == pytest.approx(TNT.rho0 * cj.D * cj.u, rel=1e-12)
    assert float(TNT.pressure(cj.rho, cj.e)) == pytest.approx(cj.p, rel=1e-12)


@pytest.mark.parametrize("changes, message", [
    ({"A": -1.0}, r"^JWL constant A of TNT must be a finite number > 0; got -1\.0\.$"),
    ({"omega": math.nan}, r"^JWL constant omega of TNT must be a finite number > 0; got nan\.$"),
    ({"B": 4e12, "R2": 0.2, "e0": 1.0}, r"^the JWL constants of TNT give a pressure of -.* Pa at the initial state "
                                        r"\(rho0 = 1630 kg/m³, e0 = 1 J/kg\); it must be > 0\.$"),
])
def test_constants_that_cannot_describe_products_are_refused_in_one_sentence(changes, message):
    constants = {k: getattr(TNT, k) for k in ("A", "B", "R1", "R2", "omega", "rho0", "e0", "c_reactant")}
    with pytest.raises(InputError, match=message):
        JWL("TNT", **{**constants, **changes})
