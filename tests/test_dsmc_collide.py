"""True DSMC collisions (partmesh.particle.dsmc.collide; the solver's
collisions="larsen-borgnakke"): exact conservation per collision, the
collision rate of VHS molecules, the Larsen–Borgnakke relaxation rate and
its equilibrium, and the two limits of the solver: free-molecular flow for
a long mean free path, the Euler shock for a short one."""

import math

import numpy as np
import pytest
from scipy import special, stats
from test_dsmc_equilibrate import _cells, _moments

import partmesh
from partmesh.cases.errors import InputError
from partmesh.particle.dsmc.collide import collide


def _collide(v, e, start, dt, sigma, g_ref, omega, zeta, seed, step, sigma_g_max, z_rot=5.0):
    """Collide in place (unit cell volumes); returns (collisions, count, momentum, energy)."""
    ncell = start.size - 1
    count, momentum, energy = np.zeros(ncell), np.zeros((ncell, 3)), np.zeros(ncell)
    done = collide(v, e, start, np.ones(ncell), dt, sigma, g_ref, omega, z_rot, zeta, seed, step, sigma_g_max,
                   count, momentum, energy)
    return done, count, momentum, energy


def _vhs_rate(theta, sigma, g_ref, omega, pairs_per_particle):
    """Collisions per particle per unit time: (N − 1)/V σ_ref g_ref^(2ω−1) ⟨g^(2−2ω)⟩ at temperature θ,
    ⟨g^k⟩ = (4θ)^(k/2) Γ((3 + k)/2)/Γ(3/2) for the relative speed of two Maxwellian molecules."""
    k = 2.0 - 2.0 * omega
    mean_gk = (4.0 * theta) ** (0.5 * k) * math.gamma(0.5 * (3.0 + k)) / math.gamma(1.5)
    return pairs_per_particle * sigma * g_ref ** (2.0 * omega - 1.0) * mean_gk


@pytest.mark.parametrize("zeta", [0.0, 2.0])
def test_collisions_conserve_each_cells_momentum_and_energy_to_round_off(zeta):
    rng = np.random.default_rng(3)
    sizes = rng.integers(1, 80, 200)
    v, e, cell, start = _cells(sizes, rng, bulk=300.0, zeta=zeta)
    before = _moments(v, e, cell, sizes.size, zeta)
    # ~ 20 collisions per particle: every pair far from equilibrium, rotation exchanging
    done, *reported = _collide(v, e, start, 1.0, 0.5, 1.0, 0.74, zeta, 11, 0, np.full(sizes.size, 1.0))
    assert done > 10 * sizes.sum()
    after = _moments(v, e, cell, sizes.size, zeta)
    for b, r in zip(before, reported):
        np.testing.assert_allclose(r, b, rtol=1e-13)  # the sums the kernel reports are those it conserves
    scale = np.abs(before[1]).max(axis=1, keepdims=True) + np.sqrt(2 * before[2])[:, None]
    assert np.abs(after[1] - before[1]).max() <= 1e-12 * scale.max()
    assert np.all(np.abs(after[2] - before[2]) <= 1e-12 * before[2])
    assert np.all(e >= 0.0)


@pytest.mark.parametrize("omega", [pytest.param(0.5, marks=pytest.mark.full), 0.74,
                                   pytest.param(1.0, marks=pytest.mark.full)])
def test_collision_rate_is_that_of_vhs_molecules(omega):
    # a resting equilibrium gas at θ = 1, 100 particles per unit cell: the no-time-counter scheme's mean rate
    rng = np.random.default_rng(4)
    ncell, per = 400, 100
    v = rng.normal(0.0, 1.0, (ncell * per, 3))
    e = rng.exponential(1.0, ncell * per)
    start = np.arange(0, ncell * per + 1, per, dtype=np.int64)
    sigma, g_ref = 1e-3, 4.0 / math.sqrt(math.pi)
    rate = _vhs_rate(1.0, sigma, g_ref, omega, per - 1)
    dt = 0.05 / rate
    sigma_g_max = np.full(ncell, sigma * g_ref)  # the mean σg: too low for the fast pairs, it must adapt upwards
    total = 0
    for step in range(200):
        total += _collide(v, e, start, dt, sigma, g_ref, omega, 2.0, 5, step, sigma_g_max)[0]
    # counted after the first steps have raised the maximum: 8e4 expected collisions, 0.4 % scatter
    total = 0
    for step in range(200, 600):
        total += _collide(v, e, start, dt, sigma, g_ref, omega, 2.0, 5, step, sigma_g_max)[0]
    measured = 2.0 * total / (ncell * per * 400 * dt)
    assert measured == pytest.approx(rate, rel=0.015)


@pytest.mark.full
@pytest.mark.parametrize("omega", [0.5, 0.74])
def test_rotation_relaxes_at_the_larsen_borgnakke_rate_to_equipartition(omega):
    # rotationally cold gas (e = 0) at θ_t = 1, ζ = 2: per collision per particle the gap θ_t − θ_r shrinks at
    # (1 + ζ/3) β/(α + β)/Z_rot (α = ζ/2, β = 5/2 − ω: E[fraction to rotation] = α/(α + β) of the pooled energy,
    # the collision-weighted relative translational energy β θ_t), up to O(1/Z²) from the serial partners;
    # the end state is the microcanonical equipartition of each cell's thermal energy (about its own mean
    # velocity) over its 3(N − 1) translational and ζN rotational degrees of freedom, ε per half degree:
    # ⟨e⟩ = ε, ⟨|c|²⟩/3 = (1 − 1/N) ε; velocities Maxwellian, rotational energies exponential
    rng = np.random.default_rng(6)
    ncell, per, z_rot = 1000, 200, 5.0
    v, e = rng.normal(0.0, 1.0, (ncell * per, 3)), np.zeros(ncell * per)
    start = np.arange(0, ncell * per + 1, per, dtype=np.int64)
    peculiar = lambda: v - np.repeat(v.reshape(ncell, per, 3).mean(axis=1), per, axis=0)  # noqa: E731
    thermal = 0.5 * (peculiar() ** 2).sum(axis=1).mean()
    sigma, g_ref = 1e-3, 4.0 / math.sqrt(math.pi)
    dt = 0.02 / _vhs_rate(1.0, sigma, g_ref, omega, per - 1)
    sigma_g_max = np.full(ncell, 4.0 * sigma * g_ref)
    collisions, gap = [0.0], [(peculiar() ** 2).mean()]
    for step in range(300):
        done = _collide(v, e, start, dt, sigma, g_ref, omega, 2.0, 9, step, sigma_g_max, z_rot)[0]
        collisions.append(collisions[-1] + 2.0 * done / (ncell * per))
        gap.append((peculiar() ** 2).mean() - e.mean())
    alpha, beta = 1.0, 2.5 - omega
    expected = (1.0 + 2.0 / 3.0) * beta / (alpha + beta) / z_rot
    measured = -np.polyfit(collisions, np.log(gap), 1)[0]
    assert measured == pytest.approx(expected, rel=0.05)
    theta_t, theta_r = [], []
    for step in range(300, 1500):
        _collide(v, e, start, 5 * dt, sigma, g_ref, omega, 2.0, 9, step, sigma_g_max, z_rot)
        if step >= 700 and step % 20 == 19:  # after ~ 45 collisions per particle
            theta_t.append((peculiar() ** 2).mean())
            theta_r.append(e.mean())
    theta = thermal / (2.5 - 1.5 / per)
    assert np.mean(theta_r) == pytest.approx(theta, rel=1.5e-3)
    assert np.mean(theta_t) == pytest.approx((1.0 - 1.0 / per) * theta, rel=1.5e-3)
    sample = slice(0, 20000)
    assert stats.kstest(peculiar()[sample, 0] / math.sqrt(theta), "norm").pvalue > 1e-3
    assert stats.kstest(e[sample] / theta, "expon").pvalue > 1e-3


def test_long_mean_free_path_gives_free_molecular_flow():
    # collisionless: each side's Maxwellian streams across, ρ(x, t) = Σ ρ_s ½ erfc(±(x − x0)/(√(2θ_s) t))
    scene = partmesh.scene("sod", nx_out=100)
    ds = partmesh.run(scene, "dsmc", dx=1 / 100, ppc=400, seed=2, collisions="larsen-borgnakke", mean_free_path=1e3,
               progress=False)
    x, t = ds.x.values, ds.time.values[-1]
    free = (0.5 * special.erfc((x - 0.5) / (math.sqrt(2.0) * t))
            + 0.125 * 0.5 * special.erfc((0.5 - x) / (math.sqrt(2.0 * 0.8) * t)))
    rho = ds["rho"].isel(time=-1).values
    # each cell's count scatters like a Poisson variable about the exact one (400 to 3200 particles): the
    # standardised residuals have mean 0 and variance 1 (the Euler solution is 0.1 away near the shock)
    z = (rho - free) / np.sqrt(free * ds.attrs["particle_mass"] / 0.01)
    assert abs(z.mean()) < 0.4 and 0.7 < z.std() < 1.3  # seeds 2, 3, 4: std 1.06, 0.97, 0.80; Euler: 5
    assert ds.attrs["collisions"] < 1e-4 * ds.attrs["n_elements"] * ds.attrs["n_steps"]


@pytest.mark.full
def test_short_mean_free_path_gives_the_euler_shock():
    # λ = Δx/4: ~ 5 collisions per particle per step; sod's plateau behind the shock (exact ρ = 0.2656) and
    # the density between rarefaction tail (x ≈ 0.486) and contact (x ≈ 0.685) (0.4263) form as in the Euler
    # solution. The second window keeps clear of the contact, which collisions smear over ~0.02: measured over
    # seeds 0-5 it reads 0.418-0.433 (mean 0.427), where (0.60, 0.65) read 0.405-0.417.
    scene = partmesh.scene("sod", nx_out=200)
    ds = partmesh.run(scene, "dsmc", dx=1 / 200, ppc=100, seed=2, collisions="larsen-borgnakke", mean_free_path=1.25e-3,
               progress=False)
    x, rho = ds.x.values, ds["rho"].isel(time=-1).values
    assert rho[(x > 0.73) & (x < 0.83)].mean() == pytest.approx(0.2656, rel=0.02)
    assert rho[(x > 0.5) & (x < 0.6)].mean() == pytest.approx(0.4263, rel=0.02)


def test_collision_settings_are_checked():
    scene = partmesh.scene("sod", nx_out=50)
    with pytest.raises(InputError, match="needs mean_free_path"):
        partmesh.run(scene, "dsmc", dx=1 / 50, collisions="larsen-borgnakke", progress=False)
    with pytest.raises(InputError, match="applies only to collisions='larsen-borgnakke'"):
        partmesh.run(scene, "dsmc", dx=1 / 50, mean_free_path=1e-3, progress=False)
    with pytest.raises(InputError, match="continuum limit"):
        partmesh.run(scene, "dsmc", dx=1 / 50, collisions="larsen-borgnakke", mean_free_path=1e-6, progress=False)
    with pytest.raises(InputError, match="omega must"):
        partmesh.run(scene, "dsmc", dx=1 / 50, collisions="larsen-borgnakke", mean_free_path=1e-2, omega=0.3, progress=False)
    with pytest.raises(InputError, match="collisions must be one of"):
        partmesh.run(scene, "dsmc", dx=1 / 50, collisions="bgk", progress=False)
