"""The DSMC-study scenes (partmesh.cases.dsmc_study): their set-up and an FV run of
each against what it must show."""

import numpy as np
import pytest

import partmesh
from partmesh.compare import exact


def test_balloon_holds_the_driver_pressure_of_its_shock_and_bursts_symmetrically():
    scene = partmesh.scene("balloon_box")
    p0 = scene.parameters["p0"]
    inside = scene.initial(np.array([0.25]), np.array([0.25]), 1e-3)[3]
    assert float(inside[0]) == pytest.approx(exact.driver_pressure(1.2, scene.parameters["rho0"], p0))
    # a square box with the balloon at its centre: the flow is symmetric about the diagonal
    ds = partmesh.run(scene, "fv", dx=1e-2, t_end=1e-3, progress=False)
    p = ds["p"].isel(time=-1).values
    assert np.abs(p - p.T).max() <= 1e-9 * p.max()
    # the front reaches the wall 0.2 m away no sooner than at the initial Mach 1.2 (less the
    # smearing of three 1 cm cells) and no later than sound would
    a0 = np.sqrt(1.4 * p0 / scene.parameters["rho0"])
    wall = ds["p_probe"].sel(probe="wall").values
    arrival = ds["t_probe"].values[np.argmax(wall > 1.01 * p0)]
    assert 0.2 / (1.2 * a0) - 3 * 0.01 / (1.2 * a0) < arrival < 0.2 / a0


def test_shock_cavity_free_stream_sees_the_normal_shock():
    scene = partmesh.scene("shock_cavity")
    rho1, u1, p1 = exact.normal_shock(1.5, scene.parameters["rho0"], scene.parameters["p0"])
    ds = partmesh.run(scene, "fv", dx=2.5e-3, progress=False)
    free = ds["p_probe"].sel(probe="free")
    assert float(free.max()) == pytest.approx(p1, rel=0.03)
    # the diffracted shock reaches the cavity floor later than the free stream above it
    half = 0.5 * (p1 + scene.parameters["p0"])
    floor = ds["p_probe"].sel(probe="cavity_floor")
    t = ds["t_probe"].values
    assert float(floor.max()) > half
    assert t[np.argmax(floor.values > half)] > t[np.argmax(free.values > half)]
    assert ds["solid"].values.astype(bool).any()
