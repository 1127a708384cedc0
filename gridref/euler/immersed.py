"""Ghost-cell immersed boundaries from the scene's signed-distance shapes
(Mittal & Iaccarino 2005; Tseng & Ferziger 2003).

Every solid cell within ``band`` cells of the surface is a ghost cell. Its
state is the fluid state at the image point mirrored across the surface,
``x_I = x_G + 2|φ(x_G)| n``, interpolated bilinearly from the fluid cells
around it, with the normal velocity reversed (a slip wall):
``v_G = v_I − 2 (v_I·n) n``, ρ_G = ρ_I, p_G = p_I. Solid cells deeper
inside keep a fixed harmless state so they never disturb the time step.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np
from scipy.spatial import cKDTree

from gridref.grid import bilinear_stencil, mesh


@dataclass(frozen=True)
class ImmersedBoundary:
    """Precomputed gather tables of the ghost cells of one grid."""

    shape: tuple[int, ...]  # field layout (ny, nx)
    ghost: np.ndarray  # flat indices of ghost cells
    stencil: np.ndarray  # (n_ghost, 4) flat indices of the image-point stencil
    weights: np.ndarray  # (n_ghost, 4), zero on solid cells, rows sum to 1
    normal: np.ndarray  # (2, n_ghost) outward unit normals
    fluid: np.ndarray  # (ny, nx) bool

    def fill(self, W):
        """The primitive state ``W`` (tuple) with every ghost cell set from
        its image point."""
        image = [jnp.sum(a.ravel()[self.stencil] * self.weights, axis=-1) for a in W]
        vn = image[1] * self.normal[0] + image[2] * self.normal[1]
        image[1] = image[1] - 2.0 * vn * self.normal[0]
        image[2] = image[2] - 2.0 * vn * self.normal[1]
        return tuple(a.ravel().at[self.ghost].set(g).reshape(a.shape) for a, g in zip(W, image))

    def reset(self, U, U_solid):
        """``U`` with the solid cells put back to ``U_solid``."""
        return tuple(jnp.where(self.fluid, a, b) for a, b in zip(U, U_solid))


def union_distance(shapes, X, Y) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Signed distance to the union of ``shapes`` and the outward normal of
    the nearest one, at the points ``(X, Y)``."""
    phis = np.stack([s.signed_distance(X, Y) for s in shapes])
    nearest = np.argmin(phis, axis=0)
    phi = np.take_along_axis(phis, nearest[None], axis=0)[0]
    nx, ny = np.zeros_like(phi), np.zeros_like(phi)
    for k, shape in enumerate(shapes):
        here = nearest == k
        if np.any(here):
            nx[here], ny[here] = shape.normal(X[here], Y[here])
    return phi, nx, ny


def immersed_boundary(grid, shapes, band: float = 3.0) -> ImmersedBoundary:
    """Ghost-cell tables for ``shapes`` on the 2D ``grid``."""
    X, Y = mesh(grid)
    h = max(grid.step)
    phi, nx, ny = union_distance(shapes, X, Y)
    fluid = phi >= 0.0
    ghost_mask = (~fluid) & (phi > -band * h)
    ghost = np.flatnonzero(ghost_mask)
    g_phi, g_nx, g_ny = phi.ravel()[ghost], nx.ravel()[ghost], ny.ravel()[ghost]
    image = np.stack([X.ravel()[ghost] - 2.0 * g_phi * g_nx, Y.ravel()[ghost] - 2.0 * g_phi * g_ny], axis=1)
    stencil, weights = bilinear_stencil(grid, image)
    weights = weights * fluid.ravel()[stencil]
    total = weights.sum(axis=1)
    orphans = total <= 1e-12
    if np.any(orphans):
        fluid_idx = np.flatnonzero(fluid.ravel())
        tree = cKDTree(np.stack([X.ravel()[fluid_idx], Y.ravel()[fluid_idx]], axis=1))
        _, nearest = tree.query(image[orphans])
        stencil[orphans] = fluid_idx[nearest][:, None]
        weights[orphans] = 0.25
        total[orphans] = 1.0
    weights = weights / total[:, None]
    return ImmersedBoundary(
        shape=fluid.shape, ghost=ghost, stencil=stencil, weights=weights,
        normal=np.stack([g_nx, g_ny]), fluid=fluid,
    )
