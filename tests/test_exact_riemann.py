"""Exact Riemann solver (partmesh.compare.exact.riemann) against Toro (2009), conservation,
jump conditions, vacuum and symmetry properties."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from partmesh.compare.exact import riemann, sample, star_state
from partmesh.compare.schema import validate

GAMMA = 1.4
SOD = ((1.0, 0.0, 1.0), (0.125, 0.0, 0.1))

# Toro (2009) Table 4.1 (initial data, gamma = 1.4) and Table 4.2 (exact p*, u*, rho*_L, rho*_R).
TORO = {
    1: (SOD[0], SOD[1], 0.30313, 0.92745, 0.42632, 0.26557),
    2: ((1.0, -2.0, 0.4), (1.0, 2.0, 0.4), 0.00189, 0.0, 0.02185, 0.02185),
    3: ((1.0, 0.0, 1000.0), (1.0, 0.0, 0.01), 460.894, 19.5975, 0.57506, 5.99924),
    4: ((1.0, 0.0, 0.01), (1.0, 0.0, 100.0), 46.0950, -6.19633, 5.99242, 0.57511),
    5: ((5.99924, 19.5975, 460.894), (5.99242, -6.19633, 46.0950), 1691.64, 8.68975, 14.2823, 31.0426),
}
VACUUM_GENERATED = ((1.0, -4.0, 0.4), (1.0, 4.0, 0.4))
LEFT_VACUUM = ((0.0, 0.0, 0.0), (1.0, 0.0, 1.0))
RIGHT_VACUUM = ((1.0, 0.0, 1.0), (0.0, 0.0, 0.0))


def sound(state):
    return np.sqrt(GAMMA * state[2] / state[0]) if state[0] > 0 else 0.0


@pytest.mark.parametrize("test", sorted(TORO))
def test_star_region_matches_toro_table_4_2(test):
    left, right, p_ref, u_ref, rho_l_ref, rho_r_ref = TORO[test]
    p_star, u_star = star_state(left, right, GAMMA)
    # Table 4.2 prints six significant digits
    assert p_star == pytest.approx(p_ref, rel=1e-5, abs=5e-6)
    assert u_star == pytest.approx(u_ref, rel=1e-5, abs=5e-6)
    rho, _, p = sample(left, right, GAMMA, np.array([u_star - 1e-9, u_star + 1e-9]))
    assert rho == pytest.approx([rho_l_ref, rho_r_ref], rel=1e-5, abs=5e-6)
    assert p == pytest.approx([p_star, p_star], rel=1e-6)


def test_sod_shock_satisfies_rankine_hugoniot():
    xi = np.linspace(1.5, 2.0, 500_001)  # around the Sod shock, ahead of the contact
    rho, u, p = sample(*SOD, GAMMA, xi)
    jumps = np.flatnonzero(np.diff(rho))
    assert jumps.size == 1
    i = jumps[0]
    (r1, u1, p1), (r0, u0, p0) = (rho[i], u[i], p[i]), (rho[i + 1], u[i + 1], p[i + 1])
    assert (r0, u0, p0) == SOD[1]
    speed = (r1 * u1 - r0 * u0) / (r1 - r0)  # from the mass jump condition
    assert xi[i] <= speed <= xi[i + 1]  # the sampled jump sits where mass conservation puts it
    assert speed == pytest.approx(1.7522, abs=5e-5)  # Sod shock speed (Toro 2009 §4.3)
    w1, w0 = u1 - speed, u0 - speed  # velocities in the shock frame
    assert r1 * w1**2 + p1 == pytest.approx(r0 * w0**2 + p0, rel=1e-10)
    enthalpy = GAMMA / (GAMMA - 1.0)
    assert enthalpy * p1 / r1 + 0.5 * w1**2 == pytest.approx(enthalpy * p0 / r0 + 0.5 * w0**2, rel=1e-10)


CONSERVATION_CASES = [TORO[k][:2] for k in sorted(TORO)] + [VACUUM_GENERATED, LEFT_VACUUM, RIGHT_VACUUM]


@pytest.mark.parametrize("left,right", CONSERVATION_CASES)
def test_sampled_solution_conserves_mass_momentum_energy(left, right):
    """On [-1, 1] before any wave leaves it, d/dt of the integral of each conserved
    quantity equals the difference of the (constant) boundary fluxes."""
    fastest = max(abs(left[1]), abs(right[1])) + 2.0 / (GAMMA - 1.0) * max(sound(left), sound(right))
    t = 0.2 / fastest
    n = 2_000_000
    x = -1.0 + (np.arange(n) + 0.5) * (2.0 / n)
    rho, u, p = sample(left, right, GAMMA, x / t)

    def totals(rho, u, p):
        energy = 0.5 * rho * u**2 + p / (GAMMA - 1.0)
        return np.array([np.mean(rho), np.mean(rho * u), np.mean(energy)]) * 2.0

    def fluxes(state):
        r, v, q = state
        return np.array([r * v, r * v**2 + q, v * (0.5 * r * v**2 + q / (GAMMA - 1.0) + q)])

    initial = np.array([sum(s[0] for s in (left, right)),
                        sum(s[0] * s[1] for s in (left, right)),
                        sum(0.5 * s[0] * s[1] ** 2 + s[2] / (GAMMA - 1.0) for s in (left, right))])
    expected = initial + t * (fluxes(left) - fluxes(right))
    scale = np.array([initial[0], initial[0] * fastest, initial[2] + 0.5 * initial[0] * fastest**2])
    assert np.all(np.abs(totals(rho, u, p) - expected) <= 2e-5 * scale)


def test_vacuum_generated_in_the_middle():
    left, right = VACUUM_GENERATED
    # the vacuum fronts (Toro §4.6): u_L + 2 a_L/(gamma-1) = -front, u_R - 2 a_R/(gamma-1) = front
    front = 4.0 - 2.0 * sound(left) / (GAMMA - 1.0)
    assert front > 0.0
    p_star, u_star = star_state(left, right, GAMMA)
    assert p_star == 0.0 and np.isnan(u_star)
    xi = np.linspace(-6.0, 6.0, 12_001)
    rho, u, p = sample(left, right, GAMMA, xi)
    middle = np.abs(xi) < front - 1e-9
    assert middle.any() and np.all(rho[middle] == 0.0) and np.all(p[middle] == 0.0)
    assert np.all(rho[~middle] > 0.0) and np.all(p[~middle] > 0.0)
    assert np.all(np.isfinite(u))


@pytest.mark.parametrize("left,right,side", [(*LEFT_VACUUM, "left"), (*RIGHT_VACUUM, "right")])
def test_expansion_into_vacuum(left, right, side):
    """A rarefaction into vacuum: the gas-vacuum front moves at u -/+ 2a/(gamma-1) (Toro §4.6);
    in the fan the Riemann invariant and the entropy of the gas stay constant and
    xi is the characteristic speed u -/+ a."""
    sign = 1.0 if side == "left" else -1.0  # +1: the vacuum is on the left, the fan faces left
    gas = right if side == "left" else left
    a = sound(gas)
    front = gas[1] - sign * 2.0 * a / (GAMMA - 1.0)
    xi = np.linspace(-8.0, 8.0, 16_001)
    rho, u, p = sample(left, right, GAMMA, xi)
    vacuum = sign * (xi - front) < -1e-9
    gas_side = sign * (xi - (gas[1] + sign * a)) > 1e-9
    fan = ~vacuum & ~gas_side & (np.abs(xi - front) > 1e-9)
    assert np.all(rho[vacuum] == 0.0) and np.all(p[vacuum] == 0.0)
    np.testing.assert_array_equal(rho[gas_side], gas[0])
    assert np.all(rho[fan] > 0.0)
    c = np.sqrt(GAMMA * p[fan] / rho[fan])
    np.testing.assert_allclose(u[fan] - sign * 2.0 * c / (GAMMA - 1.0), gas[1] - sign * 2.0 * a / (GAMMA - 1.0),
                               atol=1e-12)
    np.testing.assert_allclose(p[fan] / rho[fan] ** GAMMA, gas[2] / gas[0] ** GAMMA, rtol=1e-10)
    np.testing.assert_allclose(u[fan] + sign * c, xi[fan], atol=1e-12)
    assert star_state(left, right, GAMMA) == (0.0, pytest.approx(front, rel=1e-14))


state = st.tuples(st.floats(0.05, 10.0), st.floats(-5.0, 5.0), st.floats(0.01, 100.0))
XI = np.linspace(-40.0, 40.0, 801) + 0.012345678  # off any "simple" wave speed


@settings(max_examples=60, deadline=None)
@given(left=state, right=state, c=st.floats(-10.0, 10.0))
def test_galilean_invariance(left, right, c):
    """Adding c to both velocities shifts the solution: W'(xi + c) = W(xi) + (0, c, 0)."""
    moved = [(s[0], s[1] + c, s[2]) for s in (left, right)]
    rho, u, p = sample(left, right, GAMMA, XI)
    rho_c, u_c, p_c = sample(*moved, GAMMA, XI + c)
    np.testing.assert_allclose(rho_c, rho, rtol=1e-9, atol=1e-14)
    np.testing.assert_allclose(u_c - c, u, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(p_c, p, rtol=1e-9, atol=1e-14)
    p_star, u_star = star_state(left, right, GAMMA)
    p_star_c, u_star_c = star_state(*moved, GAMMA)
    assert p_star_c == pytest.approx(p_star, rel=1e-12, abs=1e-300)
    np.testing.assert_allclose(u_star_c - c, u_star, atol=1e-10)


@settings(max_examples=40, deadline=None)
@given(left=state, right=state)
def test_mirror_symmetry(left, right):
    """Exchanging the states and reversing velocities mirrors the solution: x -> -x."""
    mirror = [(s[0], -s[1], s[2]) for s in (right, left)]
    rho, u, p = sample(left, right, GAMMA, XI)
    rho_m, u_m, p_m = sample(*mirror, GAMMA, -XI)
    np.testing.assert_allclose(rho_m, rho, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(-u_m, u, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(p_m, p, rtol=1e-10, atol=1e-14)


wide_state = st.tuples(st.floats(1e-6, 1e6), st.floats(-50.0, 50.0), st.floats(1e-8, 1e8))


@settings(max_examples=100, deadline=None)
@given(left=wide_state, right=wide_state, gamma=st.floats(1.01, 3.0))
def test_extreme_states_give_a_converged_physical_solution(left, right, gamma):
    """Density ratios up to 1e12 and pressure ratios up to 1e16: p* is the root of
    the pressure function to its round-off, and the sampled solution is finite."""
    p_star, u_star = star_state(left, right, gamma)
    xi = np.linspace(-1e4, 1e4, 4001) + 0.012345678
    rho, u, p = sample(left, right, gamma, xi)
    assert np.all(np.isfinite(rho) & np.isfinite(u) & np.isfinite(p))
    assert np.all(rho >= 0.0) and np.all(p >= 0.0)
    if p_star > 0.0:  # no vacuum: the gas on both sides of the contact is at p*, moving at u*
        _, u_c, p_c = sample(left, right, gamma, np.array([u_star, np.nextafter(u_star, np.inf)]))
        assert p_c == pytest.approx([p_star, p_star], rel=1e-12)
        assert u_c == pytest.approx([u_star, u_star], rel=1e-12, abs=1e-12)


def test_riemann_dataset_follows_the_schema():
    x = (np.arange(200) + 0.5) / 200
    ds = validate(riemann(*SOD, x, [0.0, 0.1, 0.2], case="sod"))
    assert ds.attrs["method"] == "exact" and ds.attrs["case"] == "sod"
    assert ds.attrs["dx"] == pytest.approx(1.0 / 200)
    assert ds["rho"].dims == ("time", "x") and set(ds.data_vars) == {"rho", "u", "p", "e"}
    initial = ds.isel(time=0)
    np.testing.assert_array_equal(initial["rho"], np.where(x < 0.5, 1.0, 0.125))
    np.testing.assert_array_equal(initial["u"], 0.0)
    final = ds.sel(time=0.2)
    np.testing.assert_allclose(final["e"], final["p"] / (0.4 * final["rho"]))
    assert final["rho"].sel(x=0.01, method="nearest") == 1.0  # the head of the fan is at 0.5 - 1.183 t
    assert final["rho"].sel(x=0.99, method="nearest") == 0.125


def test_riemann_dataset_with_vacuum_has_no_nan():
    x = np.linspace(-1.0, 1.0, 101)
    ds = validate(riemann(*VACUUM_GENERATED, x, [0.0, 0.1], x0=0.0, case="vacuum"))
    assert not any(np.isnan(ds[name]).any() for name in ds.data_vars)
    assert float(ds["e"].sel(time=0.1, x=0.0)) == 0.0


@pytest.mark.parametrize("left,right,gamma,match", [
    ((-1.0, 0.0, 1.0), SOD[1], 1.4, "left"),
    (SOD[0], (0.125, 0.0, 0.0), 1.4, "right"),
    (SOD[0], (0.125, 0.0), 1.4, "right"),
    (SOD[0], SOD[1], 1.0, "gamma"),
    ((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), 1.4, "vacuum"),
])
def test_bad_input_raises(left, right, gamma, match):
    with pytest.raises(ValueError, match=match):
        star_state(left, right, gamma)


def test_bad_grid_raises():
    with pytest.raises(ValueError, match="times"):
        riemann(*SOD, np.linspace(0, 1, 10), [0.2, 0.1])
    with pytest.raises(ValueError, match="x must"):
        riemann(*SOD, [0.5], [0.1])


@pytest.mark.parametrize("left,right", [TORO[k][:2] for k in sorted(TORO)] + [VACUUM_GENERATED, LEFT_VACUUM,
                                                                             RIGHT_VACUUM])
def test_one_point_equals_the_array_to_rounding(left, right):
    """An inflow face samples one point a step, by branching instead of array selection: the same
    formulas, so every point of every wave (ahead, fan, star, vacuum, the wave edges themselves) equals the
    array's value to rounding (NumPy's vectorised powers and exponentials may differ from its scalar ones in
    the last bit, depending on the processor's instructions; any branch taken wrongly would differ at once)."""
    p_star, u_star = star_state(left, right, GAMMA)
    edges = [u_star, left[1] - sound(left), right[1] + sound(right), 0.0]
    xi = np.concatenate([np.linspace(-25.0, 25.0, 501) + 0.0123, [e for e in edges if np.isfinite(e)]])
    whole = sample(left, right, GAMMA, xi)
    for k, point in enumerate(xi):
        one = sample(left, right, GAMMA, point)
        assert all(np.ndim(w) == 0 for w in one)
        for field, value in zip(whole, one):
            np.testing.assert_allclose(value, field[k], rtol=4e-16, atol=0.0, err_msg=f"ξ = {point}")
