"""Mesh solvers in JAX on uniform and block-structured grids: the finite-volume Euler reference
(method ``fv``) and the shallow-water model (method ``swe``). A run sets
JAX's precision and compilation cache when it starts
(:func:`partmesh.gridref.jax_setup.configure_jax`)."""
