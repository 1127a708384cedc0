"""The gas SPH force pass (partmesh.particle.sph.forces.rates) against a direct
all-pairs numpy evaluation of the equations in its module docstring (Price
2012, eqs. 35–36, 101–103), its independence of the chunk count, and the
exact momentum and energy conservation of the pairwise form."""

import os
import subprocess
import sys

import numpy as np
import pytest

from partmesh.particle import kernels
from partmesh.particle.neighbours import neighbour_lists
from partmesh.particle.pair_geometry import padded, periods
from partmesh.particle.sph.forces import rates

KIND = kernels.KERNELS["wendland_c6"]
GAMMA = 1.4


def _state(n_fluid, n_ghost, periodic, rng, dim=2):
    """A cloud on the unit square or cube (ghosts: the last ``n_ghost``,
    neighbours only) with random supports (about 16 neighbours in 2D, 48 in
    3D), masses, velocities and thermodynamic states."""
    N = n_fluid + n_ghost
    x = rng.uniform(0.0, 1.0, (N, dim))
    spacing = N ** (-1.0 / dim)
    s = dict(x=x, v=rng.normal(0.0, 1.0, (N, dim)), m=rng.uniform(0.5, 1.5, N) / N,
             u=rng.uniform(1.0, 3.0, N), rho=rng.uniform(0.8, 1.2, N), omega=rng.uniform(0.9, 1.1, N),
             H=rng.uniform(1.5, 3.0, N) * spacing, alpha=rng.uniform(0.0, 2.5, N), alpha_u=rng.uniform(0.0, 1.0, N))
    s["p"] = (GAMMA - 1.0) * s["rho"] * s["u"]
    s["c"] = np.sqrt(GAMMA * s["p"] / s["rho"])
    s["box"], s["half"] = periods(np.zeros(dim), np.ones(dim), periodic, dim)
    s["offsets"], s["index"] = neighbour_lists(x, s["H"], np.zeros(dim), np.ones(dim), periodic)
    return s


def _rates(s, n, chunks):
    return rates(padded(s["x"]), s["box"], s["half"], padded(s["v"]), s["m"], s["u"], s["rho"], s["p"], s["c"],
                 s["omega"], s["H"], s["alpha"], s["alpha_u"], s["offsets"], s["index"], KIND, s["x"].shape[1], n,
                 chunks)


def _direct(s, n):
    """Every documented sum over all pairs (i < n, j ≠ i), in numpy."""
    x, v, m, u, rho, p, c, om, H, al, au = (s[k] for k in ("x", "v", "m", "u", "rho", "p", "c", "omega", "H",
                                                           "alpha", "alpha_u"))
    dim = x.shape[1]
    d = x[:n, None, :] - x[None, :, :]
    d -= s["box"][:dim] * ((d > s["half"][:dim]).astype(float) - (d < -s["half"][:dim]))
    r = np.linalg.norm(d, axis=2)
    np.fill_diagonal(r[:, :n], 10.0)  # beyond every support: no self term
    e = d / r[..., None]
    Fi = kernels.dwdr("wendland_c6", r, H[:n, None], dim)
    Fj = kernels.dwdr("wendland_c6", r, H[None, :], dim)
    Fbar = 0.5 * (Fi + Fj)
    dv = v[:n, None, :] - v[None, :, :]
    w = np.einsum("ijk,ijk->ij", dv, e)
    rho_bar = 0.5 * (rho[:n, None] + rho[None, :])
    alpha_ij = 0.5 * (al[:n, None] + al[None, :])
    vsig = 0.5 * (c[:n, None] + c[None, :]) - np.where(w < 0, alpha_ij * w, 0.0)
    Pi = np.where(w < 0, -alpha_ij * vsig * w / rho_bar, 0.0)
    pt = p / (om * rho**2)
    f = m[None, :] * (pt[:n, None] * Fi + pt[None, :] * Fj + Pi * Fbar)
    dvdt = -np.einsum("ij,ijk->ik", f, e)
    cond = 0.5 * (au[:n, None] + au[None, :]) * np.sqrt(np.abs(p[:n, None] - p[None, :]) / rho_bar)
    du_ij = u[:n, None] - u[None, :]
    dudt = (pt[:n] * np.sum(m * w * Fi, axis=1) + 0.5 * np.sum(m * Pi * w * Fbar, axis=1)
            + np.sum(m * cond * du_ij / rho_bar * Fbar, axis=1))
    div_v = -np.sum(m * w * Fi, axis=1) / (om[:n] * rho[:n])
    # |Σ_j m_j (v_ij × x̂_ij) F_i|: only the z component in 2D
    twist = np.cross(dv, e) if dim == 3 else (dv[..., 0] * e[..., 1] - dv[..., 1] * e[..., 0])[..., None]
    curl_v = np.linalg.norm(np.sum((m * Fi)[..., None] * twist, axis=1), axis=1) / (om[:n] * rho[:n])
    inside = r < np.maximum(H[:n, None], H[None, :])
    vsig_max = np.maximum(c[:n], np.max(np.where(inside, vsig, 0.0), axis=1))
    lap_u = 2.0 * np.sum(m / rho * du_ij * Fi / r, axis=1)
    return dvdt, dudt, div_v, curl_v, vsig_max, lap_u, int(inside.sum())


@pytest.mark.parametrize("dim, periodic", [(2, (False, False)), (2, (True, True)), (3, (False, True, False)),
                                           (3, (True, True, True))])
def test_force_pass_matches_the_direct_pair_sums(dim, periodic):
    s = _state(500, 120, periodic, np.random.default_rng(5), dim)
    got, want = _rates(s, 500, 2), _direct(s, 500)
    for name, a, b in zip(("dvdt", "dudt", "div_v", "curl_v", "vsig_max", "lap_u"), got, want):
        scale = np.abs(b).max()
        assert np.abs(a - b).max() <= 1e-11 * scale, name
    assert got[-1] == want[-1]  # ordered interactions: fluid–fluid pairs twice, fluid–ghost once


@pytest.mark.parametrize("dim", [2, 3])
def test_force_pass_does_not_depend_on_the_chunk_count(dim):
    s = _state(800, 0, (True, False, True)[:dim], np.random.default_rng(6), dim)
    one = _rates(s, 800, 1)
    for chunks in (2, 3, 7):
        for a, b in zip(one[:-1], _rates(s, 800, chunks)[:-1]):
            np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.abs(a).max())


@pytest.mark.parametrize("dim", [2, 3])
def test_pairwise_forces_conserve_momentum_and_energy_to_round_off(dim):
    """Without ghosts every pair term is antisymmetric: Σ m dv/dt = 0 and
    Σ m (v·dv/dt + du/dt) = 0 (Price 2012, §4.4)."""
    s = _state(1000, 0, (True,) * dim, np.random.default_rng(7), dim)
    dvdt, dudt, *_ = _rates(s, 1000, 2)
    m, v = s["m"], s["v"]
    scale = np.sum(m * np.abs(dvdt).sum(axis=1))
    assert np.abs((m[:, None] * dvdt).sum(axis=0)).max() <= 1e-13 * scale
    power = m * (np.einsum("ij,ij->i", v, dvdt) + dudt)
    assert abs(power.sum()) <= 1e-13 * np.abs(power).sum()


#: rates of a fixed 2D cloud, written to the file argv[1]; prints whether numba compiled them or loaded them
_FIXED_RATES = """
import sys
import numpy as np
from partmesh.particle import kernels
from partmesh.particle.sph.forces import rates
rng = np.random.default_rng(1)
N, H = 2000, 0.05
x = np.zeros((N, 3))
x[:, :2] = rng.random((N, 2))
near = np.linalg.norm(x[:, None, :2] - x[None, :, :2], axis=-1) < H
np.fill_diagonal(near, False)
offsets = np.concatenate([[0], np.cumsum(near.sum(axis=1))]).astype(np.int64)
index = np.nonzero(near)[1].astype(np.int32)
v = np.zeros((N, 3))
v[:, :2] = rng.standard_normal((N, 2))
rho, p, c, omega = (rng.random(N) + 1.0 for _ in range(4))
out = rates(x, np.zeros(3), np.full(3, np.inf), v, np.full(N, 1e-3), rng.random(N) + 1.0, rho, p, c, omega,
            np.full(N, H), rng.random(N), rng.random(N), offsets, index, kernels.KERNELS["wendland_c6"], 2, N, 1)
np.save(sys.argv[1], np.concatenate([np.ravel(a) for a in out[:6]]))
print("loaded" if sum(rates.stats.cache_hits.values()) else "compiled")
"""


@pytest.mark.full
def test_rates_compiled_in_the_run_and_loaded_from_the_cache_give_the_same_bits(tmp_path):
    """A first run (numba compiles the rates in its process) and a later one
    (it loads them from its cache) give the same bits: with numba's
    ``fastmath=True`` they differed by up to 9e-13 of a unit acceleration
    (pair_geometry.FASTMATH)."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    how = [subprocess.run([sys.executable, "-c", _FIXED_RATES, str(tmp_path / f"{k}.npy")], env=env, check=True,
                          capture_output=True, text=True).stdout.split()[-1] for k in (1, 2)]
    assert how == ["compiled", "loaded"]
    assert np.array_equal(np.load(tmp_path / "1.npy"), np.load(tmp_path / "2.npy"))
