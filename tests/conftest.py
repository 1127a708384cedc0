"""JAX as the grid methods run it (float64, the compilation cache), for the
tests that call grid kernels without a run; and the particle methods' kernels
compiled side by side before the test workers start."""

from pathlib import Path

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
