"""JAX as the grid methods run it (float64, the compilation cache), for the
tests that call grid kernels without a run; and the particle methods' kernels
compiled side by side before the test workers start."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import partmesh as pm
from partmesh.gridref.jax_setup import configure_jax

configure_jax()

#: short runs that between them compile every numba kernel the tests meet: each method in all its
#: geometries (1D, 2D, r–z, 3D, walls and an inflow), longest compile first
WARM_PLAN = {
    "dsmc": [("sod", {"dx": 1e-2}), ("blast_wall", {"dx": 8e-3}), ("sedov", {"dx": 1 / 24}),
             ("sedov_spherical", {"dx": 1 / 24}), ("sedov_3d", {"dx": 1 / 12, "t_end": 0.1})],
    "sph": [("sod", {"dx": 1e-2}), ("blast_wall", {"dx": 8e-3}), ("sedov", {"dx": 1 / 24}),
            ("sedov_spherical", {"dx": 1 / 24})],
    "wcsph": [("dam_break", {})],
    "hybrid": [("sod", {"dx": 1e-2})],
}


def pytest_sessionstart(session):
    """Where pytest-xdist's workers run whole folders (the README's command), compile the particle methods'
    kernels first, one process per method (:func:`partmesh.warmup.warm`): each worker would otherwise compile
    every kernel its tests meet, the same kernels in each (on two cores, a fresh clone's default tier
    took 337 s so). Cached kernels load in a few seconds. A run of named test files skips it."""
    config = session.config
    if hasattr(config, "workerinput") or not config.getoption("numprocesses", None):
        return
    if any(Path(arg.split("::")[0]).is_file() for arg in config.args):
        return
    pm.warm(WARM_PLAN)


@pytest.fixture
def products_tube():
    """A products–air shock tube: TNT's products at 1 000 kg/m³ and 5 GPa filling 0.25 ≤ x ≤ 0.5 of
    ``products_contact``'s periodic tube, air at 50 kg/m³ and 50 MPa elsewhere, at rest, to 60 µs — two shocks
    into the air, two rarefactions into the products that meet at the slab's centre (where the JWL terms are a
    third of the pressure); ``products_tube(nx_out, **changes)`` the scene on ``nx_out`` output cells with
    ``changes`` (``dataclasses.replace``)."""

    def initial(x, y, dx):
        return 50.0, 0.0, 0.0, np.where((x >= 0.25) & (x <= 0.5), 5e9, 5e7)

    def made(nx_out, **changes):
        scene = pm.scene("products_contact", t_end=6e-5, u=0.0, rho_products=1000.0, rho_air=50.0, p=5e7,
                         nx_out=nx_out)
        return dataclasses.replace(scene, initial=initial, measure=None, **changes)

    return made
