"""Ensembles on Dask (partmesh.ensembles): K seeds of a stochastic method run on
a LocalCluster and averaged as moments, equal to what averaging the member
runs' moments by hand gives; deterministic methods refuse."""

import json

import numpy as np
import pytest

from partmesh.cases.errors import InputError
from partmesh.cases.registry import get
from partmesh.dispatch import run

SCENE = dict(nx_out=50)
SETTINGS = dict(dx=1 / 50, ppc=20, t_end=0.1)


@pytest.fixture(scope="module")
def ensemble_and_members():
    scene = get("sod", **SCENE)
    ensemble = run(scene, "dsmc", ensembles=3, seed=10, workers=2, **SETTINGS)
    members = [run(scene, "dsmc", seed=s, progress=False, **SETTINGS) for s in (10, 11, 12)]
    return scene, ensemble, members


@pytest.mark.full
def test_ensemble_is_the_moment_average_of_its_members(ensemble_and_members):
    scene, ensemble, members = ensemble_and_members
    assert ensemble.attrs["ensembles"] == 3 and json.loads(ensemble.attrs["seeds"]) == [10, 11, 12]
    assert ensemble.attrs["n_elements"] == sum(m.attrs["n_elements"] for m in members)
    g = scene.gamma
    rho = np.mean([m["rho"].values for m in members], axis=0)
    mom = np.mean([(m["rho"] * m["u"]).values for m in members], axis=0)
    energy = np.mean([(m["p"] / (g - 1) + 0.5 * m["rho"] * m["u"] ** 2).values for m in members], axis=0)
    u = mom / rho
    np.testing.assert_allclose(ensemble["rho"].values, rho, rtol=1e-12)
    np.testing.assert_allclose(ensemble["u"].values, u, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(ensemble["p"].values, (g - 1) * (energy - 0.5 * rho * u**2), rtol=1e-10)
    # three different draws, not one run three times
    assert not np.array_equal(members[0]["rho"].values, members[1]["rho"].values)


@pytest.mark.full
def test_ensemble_scatter_falls_like_one_over_root_k(ensemble_and_members):
    scene, ensemble, members = ensemble_and_members

    def scatter(ds):
        """Relative standard deviation of the density in the two undisturbed states."""
        rho, x = ds["rho"].isel(time=-1).values, ds.x.values
        parts = [rho[x < 0.35] / 1.0, rho[x > 0.7] / 0.125]
        return np.std(np.concatenate([q - q.mean() for q in parts]))

    # three members: sqrt(1/3) = 0.58 of one member's scatter; 32 cells estimate it to ~ 18 %
    assert scatter(ensemble) < 0.85 * np.mean([scatter(m) for m in members])


def test_deterministic_method_refuses_ensembles():
    with pytest.raises(InputError, match="deterministic"):
        run(get("sod", **SCENE), "fv", ensembles=2, dx=0.02)
