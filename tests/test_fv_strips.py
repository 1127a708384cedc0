"""The 2D grid stepped in strips of rows (``step.strip_attempt``) does, cell
by cell, the whole grid's arithmetic: states and time steps bit-identical,
side forces to round-off, on every boundary kind, in r–z, and with cells
held first order by the positivity fallback."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from partmesh.gridref.euler import step
from partmesh.gridref.jax_setup import configure_jax


@pytest.fixture(autouse=True, scope="module")
def _float64():
    configure_jax()


def _stepped(monkeypatch, cells, kinds, radial, U0, steps=3, dt=2e-4):
    """The states, CFL steps, side forces and floor counts of ``steps``
    steps of a grid of 64 columns with strips of at most ``cells`` cells (0: the
    grid whole)."""
    monkeypatch.setattr(step, "STRIP_CELLS", cells)
    nx = U0[0].shape[1]
    scheme = step.Scheme(gamma=1.4, dx=(1.0 / nx, 1.0 / nx), kinds=kinds, radial=radial)
    inflow = jnp.asarray(1.0 + 0.1 * np.arange(16.0).reshape(4, 4))
    stepper = step.Stepper(scheme, inflow=lambda t: inflow)
    state, out = stepper.start(tuple(jnp.asarray(u) for u in U0)), []
    for _ in range(steps):
        state, dt_next, _, forces = stepper.one_step(state, 0.0, dt)
        out.append((np.stack([np.asarray(u) for u in state[0]]), float(dt_next), np.asarray(forces),
                    np.asarray(state[1])))
    return out


def _blast(ny=96, nx=64):
    """A smooth density field in a slow shear with a narrow pressure peak."""
    y, x = np.meshgrid((np.arange(ny) + 0.5) / nx, (np.arange(nx) + 0.5) / nx, indexing="ij")
    rho = 1 + 0.3 * np.sin(7 * x) * np.cos(5 * y)
    p = 1 + 50 * np.exp(-((x - 0.2) ** 2 + (y - 0.3) ** 2) * 200)
    u = 0.1 * np.cos(3 * y)
    v = -0.05 * np.ones_like(x)
    return rho, rho * u, rho * v, p / 0.4 + 0.5 * rho * (u ** 2 + v ** 2)


@pytest.mark.parametrize("kinds, radial, ny", [
    (("reflect",) * 4, 0, 96),
    (("periodic", "periodic", "outflow", "inflow"), 0, 100),
    (("reflect", "outflow", "reflect", "outflow"), 1, 100),
    pytest.param(("reflect",) * 4, 0, 100, marks=pytest.mark.full),
    pytest.param(("periodic", "periodic", "outflow", "inflow"), 0, 96, marks=pytest.mark.full),
    pytest.param(("inflow", "outflow", "periodic", "periodic"), 0, 96, marks=pytest.mark.full),
    pytest.param(("inflow", "outflow", "periodic", "periodic"), 0, 100, marks=pytest.mark.full),
    pytest.param(("reflect", "outflow", "reflect", "outflow"), 1, 96, marks=pytest.mark.full),
])
def test_strips_equal_the_whole_grid(monkeypatch, kinds, radial, ny):
    """Three strips of 32 rows, or four whose last overlaps the third."""
    whole = _stepped(monkeypatch, 0, kinds, radial, _blast(ny))
    strips = _stepped(monkeypatch, 2048, kinds, radial, _blast(ny))
    for (U_a, dt_a, f_a, _), (U_b, dt_b, f_b, _) in zip(whole, strips):
        np.testing.assert_array_equal(U_a, U_b)
        assert dt_a == dt_b
        np.testing.assert_allclose(f_a, f_b, rtol=1e-13, atol=1e-13 * np.abs(f_a).max())


def test_strips_take_the_cells_allowed_second_order(monkeypatch):
    """A redone step (the positivity fallback) passes the cells still
    allowed second order: the strips read them and return the cells whose
    face states were physical as the whole grid's pipeline does."""
    scheme = step.Scheme(gamma=1.4, dx=(1 / 64, 1 / 64), kinds=("outflow", "reflect", "periodic", "inflow"))
    U = tuple(jnp.asarray(u) for u in _blast())
    states = jnp.asarray(1.0 + 0.1 * np.arange(16.0).reshape(4, 4))
    allowed = jnp.asarray(np.random.default_rng(3).random((98, 66)) > 0.2)
    rows = 28  # the last of four strips overlaps the third

    @jax.jit
    def both(U, allowed, gate):
        Wg = step.ghosted_primitive(U, states, scheme)
        slopes = step.slopes_of(Wg, scheme)
        Wh, ok = step.half_step(Wg, slopes, 2e-4, scheme, allowed)
        fluxes = [step.face_flux(Wh, slopes[d], ok, d, scheme) for d in range(2)]
        U_new, forces = step.flux_update(U, fluxes, 2e-4, scheme, Wh)
        whole = (U_new, ok, forces, step.stable_dt(U_new, 1.4, scheme.dx, scheme.cfl))
        return whole, step.strip_attempt(step.Paired.of(U), allowed, 2e-4, scheme, rows, gate, states)

    whole, strips = both(U, allowed, jnp.array(True))
    assert not bool(jnp.all(whole[1])), "no cell was first order: the test lost its point"
    assert int(strips[0].current) == 1
    np.testing.assert_array_equal(np.stack(whole[0]), np.stack(strips[0].state()))
    # the state stepped from is still there, in the other half: a step redone reads it
    np.testing.assert_array_equal(np.stack([np.asarray(h[0]) for h in strips[0].halves]), np.stack(U))
    np.testing.assert_array_equal(whole[1], strips[1])
    np.testing.assert_allclose(whole[2], strips[2], rtol=1e-13, atol=1e-13 * float(jnp.abs(whole[2]).max()))
    assert float(whole[3]) == float(strips[3])


def test_strip_rows_fit_the_caches():
    assert step.strip_rows((2048, 2048)) == step.STRIP_CELLS // 2048
    assert step.strip_rows((614, 614)) == step.STRIP_CELLS // 614  # 614 = 2 · 307: the last strip overlaps
    assert step.strip_rows((16, 64)) == 8  # at least two strips
    assert step.strip_rows((40, 10 ** 5)) == 4  # at least four rows
    assert step.strip_rows((7, 512)) is None  # too few rows to split
    assert step.strip_rows((512,)) is None  # 1D


def test_a_charge_s_strips_equal_the_whole_grid_its_air_stepped_as_the_gas(monkeypatch):
    """Detonation products in the lower rows of an r–z grid: the strips without explosive are stepped with the
    air's ideal-gas kernels (:func:`partmesh.gridref.euler.step.strip_attempt`), the others with the mixture's;
    over three steps the state equals the whole grid's (the mixture's kernels everywhere) to rounding, and the
    air's scalars stay exactly zero."""
    from partmesh.compare.materials import TNT
    from partmesh.gridref.euler.mixture import Mixture
    from partmesh.gridref.euler.state import conservative

    gas = Mixture(TNT, 1.4, TNT.cj_state().D)
    ny, nx = 96, 64
    y, x = np.meshgrid((np.arange(ny) + 0.5) / nx, (np.arange(nx) + 0.5) / nx, indexing="ij")
    alpha = np.clip((0.2 - np.hypot(x, y)) * nx + 0.5, 0.0, 1.0)  # a quarter disc of products, its edge one cell
    rho_y = 50.0 * alpha
    rho = rho_y + (1.0 - alpha) * 1.2
    W = (rho, 0.0 * x, 0.0 * x, rho_y, rho_y, alpha, 1e5 + 5e6 * alpha)
    U0 = tuple(jnp.asarray(u) for u in conservative(tuple(jnp.asarray(a) for a in W), gas))
    scheme = step.Scheme(gamma=1.4, dx=(1.0 / nx, 1.0 / nx), kinds=("reflect", "outflow", "reflect", "outflow"),
                         radial=1, mixture=gas)
    results = []
    for cells in (32 * nx, 0):
        monkeypatch.setattr(step, "STRIP_CELLS", cells)
        stepper = step.Stepper(scheme)
        state = stepper.start(U0)
        for _ in range(3):
            state, dt_next, _, _ = stepper.one_step(state, 0.0, 2e-7)
        results.append((np.stack([np.asarray(u) for u in state[0]]), float(dt_next)))
    (strips, dt_strips), (whole, dt_whole) = results
    for k, (a, b) in enumerate(zip(strips, whole)):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(b).max(), err_msg=f"variable {k}")
    assert dt_strips == pytest.approx(dt_whole, rel=1e-12)
    assert np.all(strips[3:6, 40:] == 0.0)  # the rows above the products: air, scalars exactly zero


def test_steps_redone_by_the_fallback_are_the_same_in_strips(monkeypatch):
    """Noh's implosion on 64² cells redoes steps with cells first order (the positivity fallback): a redone step
    reads the state it started from, which the strips keep in the other half of their pair
    (:class:`~partmesh.gridref.euler.step.Paired`) while they write the new one; the run equals the whole grid's."""
    import partmesh
    from partmesh.gridref.euler import solve

    results = []
    for cells in (step.STRIP_CELLS, 0):
        monkeypatch.setattr(step, "STRIP_CELLS", cells)
        monkeypatch.setattr(solve, "_STEPPERS", {})  # (else the second run takes the first's compiled stepper)
        ds = partmesh.run(partmesh.scene("noh", n_out=64), "fv", dx=1 / 64, t_end=0.3, progress=False)
        results.append(np.stack([ds[name].values for name in ("rho", "u", "v", "p")]))
    np.testing.assert_array_equal(*results)
