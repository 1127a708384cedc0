"""Finite volumes of revolution: the face areas and cell volumes of a grid
whose x is the distance r from a symmetry axis (``k = 1``: the r–z plane of
an axisymmetric run, or the radius of a cylinder) or from a centre
(``k = 2``: the radius of a sphere), starting at r = 0 (LeVeque 2002,
*Finite Volume Methods for Hyperbolic Problems*, §18.9).

Cell ``i`` spans ``[i Δr, (i+1) Δr]``. Per unit angle (and unit length of
the other directions) a face at radius r has area ``rᵏ`` and a cell the
volume ``∫ rᵏ dr``; the quantities here are those over ``Δr``:

    a_f = r_fᵏ,    v_i = (r_{i+1/2}^{k+1} − r_{i−1/2}^{k+1}) / ((k+1) Δr),

so a flux divergence along r is ``(a_{i+1/2} F_{i+1/2} − a_{i−1/2} F_{i−1/2}) / (v_i Δr)``,
and the pressure's share of the radial momentum equation is the source
``p g_i`` with ``g_i = (a_{i+1/2} − a_{i−1/2}) / (v_i Δr)`` (≈ k/r): the two
cancel exactly for a uniform pressure, so a gas at rest stays at rest
(well balanced). The same ``g_i`` is the geometric term of the primitive
equations, ``ρ_t + … = −g ρ u_r`` and ``p_t + … = −g γ p u_r``.
A cell on the far side of the axis (i < 0) is the mirror image of one
inside: its ``g`` has the opposite sign, as its velocity has.
"""

from __future__ import annotations

import numpy as np

#: geometry name -> k, the power of r in the face areas
GEOMETRIES = {"planar": 0, "axisymmetric": 1, "spherical": 2}
#: k -> the angle of a whole revolution (per unit angle -> whole body): 1, 2π, 4π
REVOLUTION = {0: 1.0, 1: 2.0 * np.pi, 2: 4.0 * np.pi}


def face_areas(first: int, n: int, dr: float, k: int) -> np.ndarray:
    """``a_f = r_fᵏ`` of the ``n`` faces ``first, first+1, …`` (face ``i`` at r = i Δr)."""
    return ((first + np.arange(n + 0.0)) * dr) ** k


def cell_volumes(first: int, n: int, dr: float, k: int) -> np.ndarray:
    """``v_i``, the mean of ``rᵏ`` over each of the ``n`` cells ``first, first+1, …``."""
    r = (first + np.arange(n + 1.0)) * dr
    return np.diff(r ** (k + 1)) / ((k + 1) * dr)


def hoop(first: int, n: int, dr: float, k: int) -> np.ndarray:
    """``g_i = (a_{i+1/2} − a_{i−1/2}) / (v_i Δr)`` of the ``n`` cells ``first, …`` (≈ k / r)."""
    return np.diff(face_areas(first, n + 1, dr, k)) / (cell_volumes(first, n, dr, k) * dr)


def revolved(shape: tuple[int, ...], dr: float, k: int) -> np.ndarray | float:
    """The factor from a cell's planar area (or length) to its volume, on a
    grid of ``shape`` (field layout ``([y,] x)``) and radial spacing ``dr``:
    the whole turn times the cell's mean ``rᵏ`` (2π r_c in r–z); 1 when planar."""
    if k == 0:
        return 1.0
    return REVOLUTION[k] * np.broadcast_to(cell_volumes(0, shape[-1], dr, k), shape)
