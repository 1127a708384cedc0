"""What passes between the particles and the coarse grid of ``hybrid``.

* :func:`deposited`: particles' mass, momentum and total energy put on
  cells by cloud-in-cell weights (:func:`cloud`: the bilinear weights of
  the cell centres around a particle), kept only on the cells that own
  particles. The particle cells get the clouds of the fluid particles and
  the inward parts of the boundary particles' clouds, so a cell at the
  edge of the particle region is not biased by the clouds cut there.
* :func:`matched`: the fluid particles changed so that the parts of their
  clouds on the particle cells hold given totals — mass by a common
  factor, momentum by a common velocity shift (not across a wall the
  particle cells meet), internal energy by a common factor (which keeps
  it positive). The grid's finite-volume step fixes
  what the particle cells must hold after a step (their content before
  plus the flux through their edge); matching the particles to it (less
  the boundary particles' part) makes the coupled system conserve to
  round-off.
* :func:`interpolated`: the grid's primitive state at points, for the
  boundary particles.
"""

from __future__ import annotations

import dataclasses

import numpy as np


def cloud(stencil, owned: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cloud-in-cell weights of particles on the owned cells: the bilinear
    ``stencil`` ``(index, weight)`` (each ``(n, 2**d)``) with the weights
    of cells not ``owned`` (flat bool) set to zero."""
    index, weight = stencil
    return index, weight * owned[index]


def deposited(weights, m, v, u, n_cells: int, volume: float) -> np.ndarray:
    """Conservative variables (ρ, ρu[, ρv], E) per cell, (2 + d, n_cells),
    from particles of mass ``m``, velocity ``v`` (n, d) and specific
    internal energy ``u`` deposited with the cloud ``weights``."""
    index, w = weights
    per_particle = [m, *(m * v[:, d] for d in range(v.shape[1])), m * (u + 0.5 * np.sum(v * v, axis=1))]
    flat = index.ravel()
    return np.stack([np.bincount(flat, (w * q[:, None]).ravel(), n_cells) for q in per_particle]) / volume


def matched(P, share: np.ndarray, target: np.ndarray, axes=None):
    """The particles ``P`` (fields ``m``, ``v``, ``u``) changed so that the
    parts of them that ``share`` (per particle, in (0, 1]) counts hold the
    totals ``target`` (mass, momentum, total energy) exactly: masses times
    a common factor, then velocities shifted by a common vector along
    ``axes`` (bool per axis; default all), then internal energies times a
    common factor (so they stay positive). Along an axis left out the
    particles keep their momentum: where the region meets a wall across
    that axis, the grid's and the particles' walls push differently and
    neither total is the other's to match. Raises ``FloatingPointError``
    if the internal energy left would not be positive."""
    d = P.v.shape[1]
    m = P.m * (target[0] / float(P.m @ share))
    ms = m * share
    shift = (target[1:1 + d] - ms @ P.v) / target[0]
    v = P.v + (shift if axes is None else np.where(axes, shift, 0.0))
    internal = target[-1] - 0.5 * float(ms @ np.sum(v * v, axis=1))
    if not internal > 0.0:
        raise FloatingPointError(f"the particle region's internal energy would be {internal:.3g} after matching "
                                 "the grid's totals")
    return dataclasses.replace(P, m=m, v=v, u=P.u * (internal / float(ms @ P.u)))


def interpolated(W, stencil) -> np.ndarray:
    """Primitive fields ``W`` (k, [ny,] nx) at points, by the bilinear
    ``stencil`` ``(index, weight)``: (k, n)."""
    index, weight = stencil
    flat = np.asarray(W).reshape(len(W), -1)
    return np.einsum("kpj,pj->kp", flat[:, index], weight)
