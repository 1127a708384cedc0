"""JAX as the grid methods run it (float64, the compilation cache), for the
tests that call grid kernels without a run."""

from partmesh.gridref.jax_setup import configure_jax

configure_jax()
