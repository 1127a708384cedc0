"""Balls in the r–z plane of an axisymmetric scene: how much of each ring
cell a ball centred on the axis holds, in closed form, so a point blast
deposits its energy and a spherical solution is remapped onto the grid
conserving mass and energy to round-off.

A ring cell ``[r₀, r₁] × [z₀, z₁]`` (0 ≤ r₀) holds of the ball ``r² + z² < R²``
the volume

    B(R) = π ∫_{z₀}^{z₁} clip(min(r₁², R² − z²) − r₀², 0, ∞) dz,

which with ``z_a = √(R² − r₁²)``, ``z_b = √(R² − r₀²)`` (0 where negative)
is ``π (G(z₁) − G(z₀))``, ``G`` odd in z and for z ≥ 0, with
``t_a = min(z, z_a)``, ``t_b = min(z, z_b)``:

    G(z) = (r₁² − r₀²) t_a + (R² − r₀²)(t_b − t_a) − (t_b³ − t_a³)/3.

The cells of a lattice that tile the half plane r ≥ 0 hold the whole
ball between them, so their ``B`` sum to ``4πR³/3`` to round-off.
"""

from __future__ import annotations

import numpy as np


def _G(z, r0, r1, R):
    """``G(z)`` of the module docstring (odd in z)."""
    s = np.sign(z)
    z = np.abs(z)
    za = np.sqrt(np.maximum(R * R - r1 * r1, 0.0))
    zb = np.sqrt(np.maximum(R * R - r0 * r0, 0.0))
    ta, tb = np.minimum(z, za), np.minimum(z, zb)
    return s * ((r1 * r1 - r0 * r0) * ta + (R * R - r0 * r0) * (tb - ta) - (tb ** 3 - ta ** 3) / 3.0)


def ball_in_cells(r, z, dx: float, R) -> np.ndarray:
    """The volume [m³] of the ball of radius ``R`` at the origin inside each
    ring cell of side ``dx`` centred at ``(r, z)`` (r ≥ dx/2), revolved whole."""
    r, z = np.asarray(r, float), np.asarray(z, float)
    r0, r1 = np.maximum(r - 0.5 * dx, 0.0), r + 0.5 * dx
    return np.pi * (_G(z + 0.5 * dx, r0, r1, R) - _G(z - 0.5 * dx, r0, r1, R))


def ring_volumes(r, dx: float) -> np.ndarray:
    """The volume [m³] of the ring cells of side ``dx`` centred at radius ``r``: 2π r dx²."""
    r0, r1 = np.maximum(np.asarray(r, float) - 0.5 * dx, 0.0), np.asarray(r, float) + 0.5 * dx
    return np.pi * (r1 * r1 - r0 * r0) * dx


def ball_density(r, z, radius: float, dx: float) -> np.ndarray:
    """A deposit spread evenly over the ball of ``radius`` at the origin,
    per unit volume and per unit of the whole ball's total, in each ring
    cell of side ``dx`` centred at ``(r, z)``: the cell's share of the ball
    over its volume, over the ball's volume. On a lattice with edges on
    the axes the deposit sums to the total held by the part of the ball it
    covers (a half for the quadrant z ≥ 0) to round-off."""
    return ball_in_cells(r, z, dx, radius) / (ring_volumes(r, dx) * (4.0 / 3.0) * np.pi * radius ** 3)


def shells_remapped(r, z, dx: float, edges: np.ndarray, contents: np.ndarray, outside) -> np.ndarray:
    """The mean of a spherically symmetric quantity over each ring cell of
    side ``dx`` centred at ``(r, z)``, from its means ``contents`` (k,)
    over the shells between the radii ``edges`` (k + 1,), increasing from 0,
    and the value ``outside`` beyond the last: the overlap of every cell
    with every shell, B(R_{k+1}) − B(R_k), weights each shell's mean, so the
    cells hold exactly what the shells they cover held."""
    r, z = np.broadcast_arrays(np.asarray(r, float), np.asarray(z, float))
    shape = r.shape
    r, z = r.ravel(), z.ravel()
    volume = ring_volumes(r, dx)
    out = np.full(r.size, float(outside)) * volume
    near = np.hypot(np.maximum(r - 0.5 * dx, 0.0), np.maximum(np.abs(z) - 0.5 * dx, 0.0)) < edges[-1]
    if not np.any(near):
        return out.reshape(shape) / volume.reshape(shape)
    rn, zn = r[near], z[near]
    far = np.hypot(rn + 0.5 * dx, np.abs(zn) + 0.5 * dx)
    first = np.searchsorted(edges, np.hypot(np.maximum(rn - 0.5 * dx, 0.0), np.maximum(np.abs(zn) - 0.5 * dx, 0.0)),
                            side="right") - 1
    last = np.minimum(np.searchsorted(edges, far, side="left"), len(edges) - 1)
    total = np.zeros(rn.size)
    inside = np.zeros(rn.size)  # B at the lower edge of the shell under way
    for j in range(int(np.max(last - first)) + 1):
        k = first + j
        active = k < last
        kk = np.minimum(k, len(contents) - 1)
        upper = np.where(active, ball_in_cells(rn, zn, dx, edges[np.minimum(k + 1, len(edges) - 1)]), inside)
        total += np.where(active, contents[kk] * (upper - inside), 0.0)
        inside = upper
    total += float(outside) * (volume[near] - inside)
    out[near] = total
    return (out / volume).reshape(shape)
