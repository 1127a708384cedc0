"""Noh's implosion (partmesh.compare.exact.noh): Noh's published states and conservation by quadrature."""

import numpy as np
import pytest
from scipy.integrate import quad

from partmesh.compare.exact import noh, noh_profile
from partmesh.compare.schema import validate

GEOMETRIES = {"planar": 1, "cylindrical": 2, "spherical": 3}
MEASURE = {1: 1.0, 2: 2.0 * np.pi, 3: 4.0 * np.pi}  # planar: the half-line r >= 0


@pytest.mark.parametrize("geometry,rho_post", [("planar", 4.0), ("cylindrical", 16.0), ("spherical", 64.0)])
def test_post_shock_density_and_shock_speed(geometry, rho_post):
    """Noh (1987), gamma = 5/3, rho0 = 1, u0 = 1: shock speed 1/3, post-shock density 4^j, e = 1/2."""
    t = 0.6
    r = np.array([0.0, 0.2 - 1e-9, 0.2 + 1e-9])
    rho, u, p = noh_profile(r, t, geometry=geometry)
    assert rho[:2] == pytest.approx([rho_post, rho_post], rel=1e-14)
    assert np.all(u[:2] == 0.0) and u[2] == -1.0
    assert p[:2] / ((5.0 / 3.0 - 1.0) * rho[:2]) == pytest.approx([0.5, 0.5], rel=1e-14)
    j = GEOMETRIES[geometry]
    assert rho[2] == pytest.approx((1.0 + t / 0.2) ** (j - 1), rel=1e-7)


@pytest.mark.parametrize("geometry", GEOMETRIES)
@pytest.mark.parametrize("gamma", [5.0 / 3.0, 1.4])
def test_mass_and_energy_inside_a_radius_grow_by_the_inflow(geometry, gamma):
    """The gas inside R at time t is the gas initially inside R + u0 t; with zero
    pressure ahead of the shock its energy is u0^2/2 per unit mass."""
    j = GEOMETRIES[geometry]
    rho0, u0, t, radius = 1.3, 0.7, 0.9, 0.8
    shock = 0.5 * (gamma - 1.0) * u0 * t

    def integral(density):
        dV = lambda r: MEASURE[j] * r ** (j - 1)
        return sum(quad(lambda r: float(density(r)) * dV(r), a, b, epsabs=0.0, epsrel=1e-13)[0]
                   for a, b in ((0.0, shock), (shock, radius)))

    def mass_density(r):
        return noh_profile(r, t, gamma, rho0, u0, geometry)[0]

    def energy_density(r):
        rho, u, p = noh_profile(r, t, gamma, rho0, u0, geometry)
        return 0.5 * rho * u**2 + p / (gamma - 1.0)

    mass = rho0 * MEASURE[j] * (radius + u0 * t) ** j / j
    assert integral(mass_density) == pytest.approx(mass, rel=1e-10)
    assert integral(energy_density) == pytest.approx(0.5 * u0**2 * mass, rel=1e-10)


def test_initial_state_is_uniform_inflow():
    rho, u, p = noh_profile(np.array([0.0, 0.5, 2.0]), 0.0, geometry="spherical", p0=1e-6)
    np.testing.assert_array_equal(rho, 1.0)
    np.testing.assert_array_equal(u, -1.0)
    np.testing.assert_array_equal(p, 1e-6)


def test_noh_dataset_follows_the_schema():
    x = np.linspace(-1.0, 1.0, 40) + 0.5 * 2.0 / 39
    y = np.linspace(-1.0, 1.0, 40)
    ds = validate(noh(x, y, [0.0, 0.3, 0.6]))
    assert ds.attrs["method"] == "exact" and ds["rho"].dims == ("time", "y", "x")
    xx, yy = np.meshgrid(x, y)
    r = np.hypot(xx, yy)
    start = ds.isel(time=0)
    np.testing.assert_allclose(start["u"], -xx / r)
    np.testing.assert_allclose(start["v"], -yy / r)
    final = ds.sel(time=0.6)
    inside = r < 0.2
    assert inside.any()
    np.testing.assert_array_equal(final["rho"].values[inside], 16.0)
    np.testing.assert_allclose(final["e"].values[inside], 0.5)
    np.testing.assert_array_equal(final["u"].values[inside], 0.0)
    np.testing.assert_allclose(final["rho"].values[~inside], 1.0 + 0.6 / r[~inside])
    np.testing.assert_array_equal(final["p"].values[~inside], 1e-6)


@pytest.mark.parametrize("call,match", [
    (lambda: noh_profile([0.1], -1.0), "t must"),
    (lambda: noh_profile([0.1], 1.0, gamma=1.0), "gamma"),
    (lambda: noh_profile([0.1], 1.0, geometry="toroidal"), "geometry"),
    (lambda: noh_profile([0.1], 1.0, u0=0.0), "u0"),
    (lambda: noh([0.0, 1.0], [0.0, 1.0], [0.1], p0=0.0), "p0"),
])
def test_bad_input_raises(call, match):
    with pytest.raises(ValueError, match=match):
        call()
