"""JAX as the grid methods run it: double precision (every reference result
is float64; ``swe`` may ask for float32 arrays explicitly) and the
persistent compilation cache, so that a second run of the same problem
does not recompile. Set when a run starts (:func:`configure_jax`), not on
import."""

from __future__ import annotations

import os

import jax

#: where compiled programs are kept between runs (``PARTMESH_JAX_CACHE`` overrides it)
CACHE = os.environ.get("PARTMESH_JAX_CACHE", os.path.join(os.path.expanduser("~"), ".cache", "partmesh", "jax"))


def configure_jax() -> None:
    """Switch JAX to float64 and to the persistent compilation cache."""
    jax.config.update("jax_enable_x64", True)
    jax.config.update("jax_compilation_cache_dir", CACHE)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
