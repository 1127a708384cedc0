"""Detonation products in fv (SPEC §3.10): the mixture's equation of state against the JWL and ideal-gas
closed forms of :mod:`partmesh.compare.materials`, a products–air contact carried at constant speed, a planar
detonation against D, p_CJ and the Taylor wave, and the refusals."""

import dataclasses

import jax
import numpy as np
import pytest

import partmesh as pm
from partmesh.cases.errors import InputError
from partmesh.compare.materials import TNT
from partmesh.gridref.euler.mixture import Mixture

jax.config.update("jax_enable_x64", True)

GAS = Mixture(TNT, 1.4, TNT.cj_state().D)
RHO = np.array([200.0, 1000.0, 1630.0, 2200.0])
E = np.array([2e6, 3e6, 4.3e6, 6e6])


def _state(alpha, rho1, rho2, burnt_fraction):
    """(ρ, scalars) of a cell holding products of density ρ₁ in its share α and air of density ρ₂."""
    rho_y = alpha * rho1
    rho = rho_y + (1.0 - alpha) * rho2
    return rho, (rho_y, burnt_fraction * rho_y, alpha + 0.0 * rho)


def test_a_cell_of_burnt_products_follows_the_jwl_equation_of_state():
    rho, scalars = _state(1.0, RHO, 1.0, 1.0)
    p = np.asarray(GAS.pressure(rho, scalars, rho * E))
    np.testing.assert_allclose(p, TNT.pressure(RHO, E), rtol=1e-13)
    np.testing.assert_allclose(np.sqrt(np.asarray(GAS.stiffness(rho, scalars, p)) / rho), TNT.sound_speed(RHO, E),
                               rtol=1e-12)
    np.testing.assert_allclose(np.asarray(GAS.internal_energy(rho, scalars, p)), rho * E, rtol=1e-12)


def test_a_cell_of_air_is_an_ideal_gas():
    rho, scalars = _state(0.0, 1.0, np.array([0.5, 1.2, 8.0]), 0.0)
    p = np.asarray(GAS.pressure(rho, scalars, rho * 2.5e5))
    np.testing.assert_allclose(p, 0.4 * rho * 2.5e5, rtol=1e-14)
    np.testing.assert_allclose(np.asarray(GAS.stiffness(rho, scalars, p)), 1.4 * p, rtol=1e-14)


def test_the_unreacted_explosive_rests_at_zero_pressure_with_its_hugoniot_sound_speed():
    """The reactant at its density holding the detonation energy e₀: p = 0 and c = c_reactant."""
    rho, scalars = _state(1.0, TNT.rho0, 1.0, 0.0)
    p = float(GAS.pressure(rho, scalars, rho * TNT.e0))
    assert abs(p) < 1e-6 * TNT.cj_state().p
    assert np.sqrt(float(GAS.stiffness(rho, scalars, 0.0)) / rho) == pytest.approx(TNT.c_reactant, rel=1e-12)


def test_a_mixed_cell_holds_both_materials_at_one_pressure():
    """Products and air at one pressure p in any volume shares: the mixture's internal energy is the sum of
    the materials' (each from its own equation of state at p), and the mixture gives back p."""
    p = 3e7
    rho1, rho2 = 300.0, 30.0
    e2 = p / (0.4 * rho2)
    e1 = (p - float(TNT.pressure(rho1, 0.0))) / (TNT.omega * rho1)  # p = f(ρ₁) + ωρ₁e₁
    for alpha in (0.1, 0.5, 0.9):
        rho, scalars = _state(alpha, rho1, rho2, 1.0)
        rho_e = alpha * rho1 * e1 + (1.0 - alpha) * rho2 * e2
        assert float(GAS.pressure(rho, scalars, rho_e)) == pytest.approx(p, rel=1e-12)


def test_a_products_air_contact_keeps_its_pressure_and_velocity_and_stays_sharp():
    """A slab of products at 300 kg/m³ in air of 30 kg/m³, both at 300 MPa (the JWL terms 6 % of it) and
    200 m/s, carried once round a periodic tube of 200 cells: pressure and velocity stay uniform to 1e-8
    (measured 4.6e-12, 9.0e-11), mass and energy to round-off, and each contact is spread over no more
    than 12 cells between 1 % and 99 % products (measured 10.5; MC limiter)."""
    ds = pm.run(pm.scene("products_contact"), "fv", dx=5e-3, progress=False)
    assert ds.attrs["pressure_deviation"] < 1e-8
    assert ds.attrs["velocity_deviation"] < 1e-8
    assert abs(ds.attrs["mass_drift"]) < 1e-13 and abs(ds.attrs["energy_drift"]) < 1e-13
    assert ds.attrs["interface_cells"] <= 12
    Y = ds["Y"].isel(time=-1)
    assert float(Y.sel(x=0.375, method="nearest")) == pytest.approx(1.0, abs=1e-12)  # the slab back in place
    assert float(Y.sel(x=0.875, method="nearest")) == pytest.approx(0.0, abs=1e-12)


def test_products_expanding_into_air_stay_pure_behind_their_contacts(products_tube):
    """The products–air shock tube (``products_tube``, conftest): after 60 µs the products have expanded to
    0.07 ≤ x ≤ 0.68. Every cell the products fill (α > 0.99) holds products only (Y > 0.999: the partial
    densities are reconstructed apart, so no air mass rides on faces without air volume), and the pressure
    falls from the slab's centre through each rarefaction to the contact, monotone but for MUSCL's dip of
    1.5 % at the rarefaction's tail. (Limiting ρ and ρY apart left air in the products, Y down to 0.27, and
    pressure spikes twice the rarefaction's where the slab's edges started.)"""
    ds = pm.run(products_tube(400, fields=("rho", "u", "p", "e", "Y", "alpha")), "fv", dx=5e-4,
                progress=False).isel(time=-1)
    x, p, Y, alpha = (np.asarray(ds[f]) for f in ("x", "p", "Y", "alpha"))
    products = alpha > 0.99
    assert 0.05 < x[products].min() < 0.1 and 0.65 < x[products].max() < 0.7
    assert np.all(Y[products] > 0.999)
    centre = np.argmin(np.abs(x - 0.375))
    left = products & (x < 0.375)
    right = products & (x > 0.375)
    assert np.all(np.diff(p[left]) >= -0.01 * p[centre]) and np.all(np.diff(p[right]) <= 0.01 * p[centre])


def test_a_planar_detonation_runs_at_d_reaches_cj_and_leaves_the_taylor_wave():
    """A TNT slab of 0.1 m lit at the wall, at 0.1 mm: the front's speed within 1 % of D (measured
    −0.015 %), the largest pressure within 5 % of p_CJ (+0.9 %), and the pressure behind within 3 % of the
    Taylor wave everywhere up to 95 % of the way to the front (1.5 %; its mean 0.1 % of p_CJ)."""
    ds = pm.run(pm.scene("detonation_1d"), "fv", dx=1e-4, progress=False)
    assert abs(ds.attrs["front_speed_error"]) < 0.01
    assert ds.attrs["peak_pressure"] == pytest.approx(ds.attrs["p_cj"], rel=0.05)
    assert ds.attrs["taylor_wave_error_max"] < 0.03
    assert ds.attrs["taylor_wave_error"] < 0.005


def test_the_taylor_wave_error_falls_at_first_order():
    """The front is a captured discontinuity: the mean error behind it falls like Δx (measured 0.0038,
    0.0019 at 0.4 and 0.2 mm)."""
    errors = [pm.run(pm.scene("detonation_1d"), "fv", dx=dx, progress=False).attrs["taylor_wave_error"]
              for dx in (4e-4, 2e-4)]
    assert np.log2(errors[0] / errors[1]) > 0.8


def test_an_initiation_point_outside_the_charge_is_refused_in_one_sentence():
    with pytest.raises(InputError, match=r"^initiation must lie inside the charge, in \[0, 0\.1\] m; got 0\.2\.$"):
        pm.scene("detonation_1d", initiation=0.2)


@pytest.mark.parametrize("method, message", [
    ("dsmc", r"^method dsmc models an ideal gas only, and detonation_1d holds a charge of JWL detonation products: "
             r"run it with method fv or sph, or \(a surface burst\) with charge=balloon\.$"),
    ("hybrid", r"^method hybrid models an ideal gas only, and detonation_1d holds"),
])
def test_a_method_without_detonation_products_refuses_a_charge_in_one_sentence(method, message):
    with pytest.raises(InputError, match=message):
        pm.run(pm.scene("detonation_1d"), method, progress=False)


@pytest.mark.parametrize("options, message", [
    (dict(riemann="hll"), r"^detonation_1d holds detonation products, which fv fluxes with riemann = hllc only"),
    (dict(levels=2), r"^fv runs detonation products on a uniform 1D or 2D grid without bodies for now"),
])
def test_fv_refuses_what_it_cannot_do_with_a_charge_in_one_sentence(options, message):
    with pytest.raises(InputError, match=message):
        pm.run(pm.scene("detonation_1d"), "fv", dx=1e-3, progress=False, **options)


def test_a_jwl_surface_burst_starts_from_its_1d_sphere_with_its_mass_products_and_energy():
    """The remap of a detonated sphere onto r–z: the quadrant's cells hold half the sphere's mass, products
    mass, products volume and energy to round-off (the air beyond the sphere's reach at ambient), each cell's
    pressure the mixture's (it gives back the remapped energy)."""
    from partmesh.cases.charges import remapped, surface_burst, surface_burst_1d
    from partmesh.gridref.euler.setup import initial_state
    from partmesh.gridref.grid import solver_grid

    scene = surface_burst(charge="jwl")
    sphere = pm.run(dataclasses.replace(surface_burst_1d(t_end=2e-5, n_out=8000, charge="jwl", extent=16.0),
                                        fields=("rho", "u", "p", "e", "Y", "alpha")), "fv", progress=False)
    started = remapped(scene, sphere)
    grid = solver_grid(scene.domain, scene.domain[0][1] / 400)
    U = [np.asarray(a) for a in initial_state(started, grid)]
    dx = scene.domain[0][1] / 400
    R = (np.arange(400) + 0.5) * dx
    volume = 2.0 * np.pi * R[None, :] * dx * dx
    last = sphere.isel(time=-1)
    r1 = np.asarray(sphere.x)
    edges = np.concatenate([[0.0], 0.5 * (r1[1:] + r1[:-1]), [r1[-1] + 0.5 * (r1[1] - r1[0])]])
    shells = 4.0 / 3.0 * np.pi * np.diff(edges ** 3)
    rho0, p0 = scene.parameters["rho0"], scene.parameters["p0"]
    rho, Y, alpha = (np.asarray(last[f]) for f in ("rho", "Y", "alpha"))
    energy = rho * np.asarray(last.e) + 0.5 * rho * np.asarray(last.u) ** 2
    total = np.sum(volume * np.ones((400, 1)))
    beyond = total - 0.5 * np.sum(shells)
    assert np.sum(U[0] * volume) == pytest.approx(0.5 * np.sum(rho * shells) + rho0 * beyond, rel=1e-12)
    assert np.sum(U[3] * volume) == pytest.approx(0.5 * np.sum(rho * Y * shells), rel=1e-12)
    assert np.sum(U[5] * volume) == pytest.approx(0.5 * np.sum(alpha * shells), rel=1e-12)
    assert np.sum(U[-1] * volume) == pytest.approx(0.5 * np.sum(energy * shells) + p0 / 0.4 * beyond, rel=1e-10)
    assert np.array_equal(U[4], U[3])  # all burnt
