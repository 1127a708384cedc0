"""Shock relations (partmesh.compare.exact.shocks): published values, jump conditions,
limits, and the reflected shock checked by the exact Riemann solver."""

import numpy as np
import pytest
from scipy.integrate import quad

from partmesh.compare.exact import (
    BLASTS,
    driver_pressure,
    friedlander,
    max_deflection,
    normal_shock,
    rankine_hugoniot_inflow,
    reflected_shock,
    reflection_coefficient,
    sample,
    star_state,
    theta_beta_mach,
)

RHO0, P0, GAMMA = 1.225, 101325.0, 1.4
A0 = np.sqrt(GAMMA * P0 / RHO0)
MACHS = [1.01, 1.2, 2.0, 3.2, 5.0, 10.0]


def test_normal_shock_at_mach_3_2_matches_the_spec():
    rho, u, p = normal_shock(3.2, RHO0, P0)
    assert round(rho / RHO0, 2) == 4.03
    assert round(p / P0, 2) == 11.78
    assert round(u, 2) == 818.83


@pytest.mark.parametrize("Ms", MACHS)
def test_normal_shock_satisfies_rankine_hugoniot_in_the_shock_frame(Ms):
    rho, u, p = normal_shock(Ms, RHO0, P0)
    W = Ms * A0
    w0, w1 = -W, u - W  # gas velocities seen from the shock
    assert rho * w1 == pytest.approx(RHO0 * w0, rel=1e-12)
    assert p + rho * w1**2 == pytest.approx(P0 + RHO0 * w0**2, rel=1e-12)
    h = GAMMA / (GAMMA - 1.0)
    assert h * p / rho + 0.5 * w1**2 == pytest.approx(h * P0 / RHO0 + 0.5 * w0**2, rel=1e-12)


def test_reflection_coefficient_weak_shock_limit_is_acoustic_doubling():
    assert reflection_coefficient(1.0) == 2.0
    assert reflection_coefficient(1.0 + 1e-8) == pytest.approx(2.0, abs=1e-6)
    c_r = reflection_coefficient(np.linspace(1.2, 10.0, 50))
    assert np.all(np.diff(c_r) > 0.0) and np.all((c_r > 2.0) & (c_r < 8.0))


@pytest.mark.parametrize("gamma", [1.4, 5.0 / 3.0])
def test_reflected_over_incident_pressure_strong_shock_limit(gamma):
    shock = reflected_shock(1e4, RHO0, P0, gamma)
    assert shock["p_reflected"] / shock["p_incident"] == pytest.approx((3 * gamma - 1) / (gamma - 1), rel=1e-6)
    assert reflection_coefficient(1e4, gamma) == pytest.approx((3 * gamma - 1) / (gamma - 1), rel=1e-6)


@pytest.mark.parametrize("Ms", MACHS)
def test_reflection_coefficient_is_independent_of_the_ambient_state(Ms):
    shock = reflected_shock(Ms, RHO0, P0)
    c_r = (shock["p_reflected"] - P0) / (shock["p_incident"] - P0)
    assert c_r == pytest.approx(reflection_coefficient(Ms), rel=1e-9)


@pytest.mark.parametrize("Ms", MACHS)
def test_reflected_mach_number_satisfies_anderson_7_23(Ms):
    Mr = reflected_shock(Ms, RHO0, P0)["Mr"]
    g = GAMMA
    rhs = Ms / (Ms**2 - 1) * np.sqrt(1 + 2 * (g - 1) / (g + 1) ** 2 * (Ms**2 - 1) * (g + 1 / Ms**2))
    assert Mr / (Mr**2 - 1) == pytest.approx(rhs, rel=1e-11)


@pytest.mark.parametrize("Ms", MACHS)
def test_gas_behind_reflected_shock_is_at_rest_by_the_riemann_solver(Ms):
    """A wall is the symmetry plane of the post-shock gas colliding with its mirror image."""
    rho1, u1, p1 = normal_shock(Ms, RHO0, P0)
    shock = reflected_shock(Ms, RHO0, P0)
    p_star, u_star = star_state((rho1, u1, p1), (rho1, -u1, p1), GAMMA)
    assert p_star == pytest.approx(shock["p_reflected"], rel=1e-8)
    assert abs(u_star) <= 1e-8 * u1
    speed = shock["reflected_shock_speed"]
    assert speed > 0.0
    rho, u, _ = sample((rho1, u1, p1), (rho1, -u1, p1), GAMMA, [-speed * (1 + 1e-9), -speed * (1 - 1e-9)])
    assert rho == pytest.approx([rho1, shock["rho_reflected"]], rel=1e-8)
    assert u[1] == pytest.approx(0.0, abs=1e-8 * u1)
    # mass balance across the reflected shock, lab frame: rho1 (u1 + W) = rho_r W
    assert rho1 * (u1 + speed) == pytest.approx(shock["rho_reflected"] * speed, rel=1e-12)


def _theta_of_beta(M1, beta, gamma=GAMMA):
    """tan theta = 2 cot beta (M1^2 sin^2 beta - 1)/(M1^2 (gamma + cos 2 beta) + 2), theta in degrees."""
    m2 = M1**2
    tan_theta = 2 / np.tan(beta) * (m2 * np.sin(beta) ** 2 - 1) / (m2 * (gamma + np.cos(2 * beta)) + 2)
    return np.degrees(np.arctan(tan_theta))


def _brute_force(M1, theta_deg, branch):
    """beta by scanning the theta-beta-M relation on a fine grid and interpolating."""
    beta = np.linspace(np.arcsin(1 / M1), np.pi / 2, 2_000_001)
    theta = _theta_of_beta(M1, beta)
    peak = np.argmax(theta)
    part = slice(0, peak + 1) if branch == "weak" else slice(peak, None)
    b, th = beta[part], theta[part]
    order = np.argsort(th)
    return np.degrees(np.interp(theta_deg, th[order], b[order])), theta[peak]


@pytest.mark.parametrize("branch", ["weak", "strong"])
@pytest.mark.parametrize("theta", [10.0, 20.0, 30.0])
def test_theta_beta_mach_at_mach_3_5_against_a_brute_force_scan(theta, branch):
    reference, _ = _brute_force(3.5, theta, branch)
    assert theta_beta_mach(3.5, theta, branch=branch) == pytest.approx(reference, abs=1e-5)


def test_theta_beta_mach_textbook_value_and_limits():
    assert theta_beta_mach(2.0, 10.0) == pytest.approx(39.31, abs=0.005)  # textbook value (Anderson ch. 4)
    for M1 in (1.5, 3.5, 8.0):
        assert theta_beta_mach(M1, 1e-9) == pytest.approx(np.degrees(np.arcsin(1 / M1)), abs=1e-6)
        assert theta_beta_mach(M1, 0.0, branch="strong") == pytest.approx(90.0, abs=1e-9)
    betas = theta_beta_mach(3.5, np.array([10.0, 20.0, 30.0]))
    assert betas.shape == (3,) and np.all(np.diff(betas) > 0)


@pytest.mark.parametrize("M1", [1.5, 2.0, 3.5, 10.0])
def test_max_deflection_against_a_brute_force_scan(M1):
    _, theta_max = _brute_force(M1, 0.0, "weak")
    assert max_deflection(M1) == pytest.approx(theta_max, abs=1e-6)


def test_max_deflection_textbook_value_and_detachment():
    assert max_deflection(2.0) == pytest.approx(22.97, abs=0.005)  # textbook value (NACA Report 1135 charts)
    with pytest.raises(ValueError, match="detaches") as err:
        theta_beta_mach(3.5, 40.0)
    assert f"{max_deflection(3.5):.2f}" in str(err.value)


def test_friedlander_shape_and_positive_impulse():
    p_peak, t_plus, alpha = 1e6, 0.473e-3, 4.0
    assert friedlander(0.0, p_peak, t_plus, alpha) == p_peak
    assert friedlander(t_plus, p_peak, t_plus, alpha) == pytest.approx(0.0, abs=1e-9)
    assert friedlander(-1e-6, p_peak, t_plus, alpha) == 0.0
    # positive-phase impulse, Kinney & Graham: I+ = p_peak t+ [1/alpha - (1 - exp(-alpha))/alpha^2]
    impulse = quad(lambda t: friedlander(t, p_peak, t_plus, alpha), 0.0, t_plus, epsrel=1e-12)[0]
    assert impulse == pytest.approx(p_peak * t_plus * (1 / alpha - (1 - np.exp(-alpha)) / alpha**2), rel=1e-10)
    t = np.linspace(-1e-3, 5e-3, 60_001)
    p = friedlander(t, p_peak, t_plus, alpha)
    assert p.shape == t.shape
    # the underpressure minimum: at t+ (1 + 1/alpha), -p_peak/alpha exp(-(1 + alpha))
    assert p.min() == pytest.approx(-p_peak / alpha * np.exp(-(1 + alpha)), rel=1e-6)
    assert t[np.argmin(p)] == pytest.approx(t_plus * (1 + 1 / alpha), abs=1e-7)
    none = friedlander(t, p_peak, t_plus, alpha, negative_phase="none")
    np.testing.assert_array_equal(none[t > t_plus], 0.0)
    np.testing.assert_array_equal(none[t <= t_plus], p[t <= t_plus])


@pytest.mark.parametrize("Ms", MACHS)
def test_rankine_hugoniot_inflow_agrees_with_normal_shock(Ms):
    rho1, u1, p1 = normal_shock(Ms, RHO0, P0)
    rho, u, p = rankine_hugoniot_inflow(p1 - P0, RHO0, P0)
    assert (rho, u, p) == pytest.approx((rho1, u1, p1), rel=1e-12)


def test_rankine_hugoniot_inflow_is_vectorised_over_a_blast():
    blast = BLASTS["moderate"]
    p0 = 1e5
    t = np.linspace(0.0, 3e-3, 301)
    p_over = friedlander(t, blast["p_peak_ratio"] * p0, blast["t_plus"], blast["alpha"])
    rho, u, p = rankine_hugoniot_inflow(p_over, 1.0, p0)
    assert rho.shape == u.shape == p.shape == t.shape
    assert p[0] == pytest.approx((1 + blast["p_peak_ratio"]) * p0)
    assert rankine_hugoniot_inflow(0.0, 1.0, p0) == (1.0, 0.0, p0)
    assert np.all(np.sign(u) == np.sign(p_over))


@pytest.mark.parametrize("call,match", [
    (lambda: normal_shock(0.9, RHO0, P0), "Ms"),
    (lambda: normal_shock(2.0, -1.0, P0), "rho0"),
    (lambda: normal_shock(2.0, RHO0, P0, gamma=0.9), "gamma"),
    (lambda: theta_beta_mach(1.0, 5.0), "M1"),
    (lambda: theta_beta_mach(2.0, -1.0), "theta_deg"),
    (lambda: theta_beta_mach(2.0, 5.0, branch="middle"), "branch"),
    (lambda: friedlander(0.0, 1.0, 0.0, 1.0), "t_plus"),
    (lambda: friedlander(0.0, 1.0, 1.0, 1.0, negative_phase="linear"), "negative_phase"),
    (lambda: rankine_hugoniot_inflow(-2e5, 1.0, 1e5), "p_over"),
])
def test_bad_input_raises(call, match):
    with pytest.raises(ValueError, match=match):
        call()


@pytest.mark.parametrize("Ms", [1.2, 2.0, 3.2])
def test_driver_pressure_sends_a_shock_of_the_asked_mach(Ms):
    # the exact Riemann solution of the burst: the shock front moves at Ms·a0
    rho0, p0, gamma = 1.225, 101325.0, 1.4
    p4 = driver_pressure(Ms, rho0, p0, gamma)
    a0 = np.sqrt(gamma * p0 / rho0)
    lo, hi = 0.0, 10.0 * a0  # bracket the front's speed: moving gas behind it, gas at rest ahead
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        u = sample((rho0, 0.0, p4), (rho0, 0.0, p0), gamma, np.array([mid]))[1][0]
        lo, hi = (mid, hi) if u > 1e-9 * a0 else (lo, mid)
    assert lo / a0 == pytest.approx(Ms, rel=1e-9)
    assert p4 > p0 * (1.0 + 2.0 * gamma / (gamma + 1.0) * (Ms**2 - 1.0))  # it drives, and expands
