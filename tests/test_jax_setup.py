"""How a grid run sets up the process: float64 JAX and glibc's heap kept
for the step's arrays (:mod:`partmesh.gridref.jax_setup`)."""

import platform

import jax.numpy as jnp
import pytest

from partmesh.gridref.jax_setup import configure_jax, keep_freed_memory


def test_a_grid_run_computes_in_double_precision():
    configure_jax()
    assert jnp.asarray(1.0).dtype == jnp.float64
    assert float(jnp.asarray(1.0) + 1e-15) != 1.0


@pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="the settings are glibc's malloc's")
def test_glibc_takes_both_heap_settings():
    """Both settings are taken (glibc's mallopt returns 0 for one it refuses)."""
    assert keep_freed_memory()
