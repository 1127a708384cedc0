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

from typing import NamedTuple

import jax.numpy as jnp
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


class Rings(NamedTuple):
    """The geometry of revolution a step of a batch of cells reads, for
    cells at any global radial indices (a whole grid, or blocks laid side
    by side): ``hoop``, ``g`` of the cells of the step's interior and one
    ghost layer (the predictor's cells); ``areas``, ``a_f`` of the radial
    faces of the interior; ``volumes``, ``v`` of the interior's cells;
    ``crowding``, the CFL rate's factor of every interior cell,
    ``max(1, (a_{i−1/2} + a_{i+1/2}) / (2 v_i))``."""

    hoop: np.ndarray
    areas: np.ndarray
    volumes: np.ndarray
    crowding: np.ndarray


class RadialTable:
    """``a``, ``v`` and ``g`` of every cell ``i`` of a radial axis of ``n``
    cells of ``Δr``, and ``ghosts`` cells beyond either end (entry ``i +
    ghosts``; the face of cell ``i`` is its lower one). Beyond a reflecting
    outer side (``outer_reflect``) a ghost cell is the mirror image of one
    inside: its ``g`` has the opposite sign. The values are those of
    :func:`face_areas`, :func:`cell_volumes` and :func:`hoop` whatever the
    cells they are read for, so a batch of blocks steps with the very
    numbers of the whole grid."""

    def __init__(self, n: int, dr: float, k: int, ghosts: int, outer_reflect: bool):
        self.ghosts, self.k = ghosts, k
        first, m = -ghosts, n + 2 * ghosts
        self.areas = face_areas(first, m, dr, k)
        self.volumes = cell_volumes(first, m, dr, k)
        self.hoop = hoop(first, m, dr, k)
        if outer_reflect:
            inside = self.hoop[ghosts + n - 1: ghosts + n - 1 - ghosts: -1]
            self.hoop[ghosts + n:] = -inside
        upper = face_areas(first + 1, m, dr, k)
        self.crowding = np.maximum(1.0, 0.5 * (self.areas + upper) / self.volumes)

    def volumes_at(self, i):
        """``v`` of the cells at global indices ``i`` (numpy or JAX)."""
        return _taken(self.volumes, i + self.ghosts)

    def crowding_at(self, i):
        """The CFL rate's factor of the cells at global indices ``i``."""
        return _taken(self.crowding, i + self.ghosts)

    def areas_at(self, i):
        """``a_f`` of the lower faces of the cells at global indices ``i``."""
        return _taken(self.areas, i + self.ghosts)

    def rings(self, i) -> Rings:
        """The :class:`Rings` of a step whose interior and one ghost layer
        are the cells at global radial indices ``i`` (numpy or JAX integers,
        laid out ``([y,] x)`` or along x alone)."""
        inner = (slice(1, -1),) * i.ndim
        faces = inner[:-1] + (slice(1, None),)
        return Rings(hoop=_taken(self.hoop, i + self.ghosts), areas=self.areas_at(i[faces]),
                     volumes=self.volumes_at(i[inner]), crowding=self.crowding_at(i[inner]))


def _taken(table: np.ndarray, index):
    """``table[index]``: numpy for a numpy index, on the device for a JAX one."""
    if isinstance(index, np.ndarray):
        return table[index]
    return jnp.asarray(table)[index]
