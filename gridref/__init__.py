"""Mesh solvers in JAX on jax-cfd grids: the finite-volume Euler reference
(method ``fv``) and the shallow-water model (method ``swe``).

Importing ``gridref`` switches JAX to float64 (every reference result is
double precision) and turns on JAX's persistent compilation cache, so a
second run of the same problem does not recompile.
"""

import os

import jax

jax.config.update("jax_enable_x64", True)
jax.config.update(
    "jax_compilation_cache_dir",
    os.environ.get("PARTMESH_JAX_CACHE", os.path.join(os.path.expanduser("~"), ".cache", "partmesh", "jax")),
)
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
