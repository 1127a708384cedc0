r"""The state of the wall and virtual particles of gas SPH, every step: the
skew-gradient wall treatment of Prasanna Kumar, Patnaik & Ramamurthi
(2018), Phys. Fluids 30, 046105 (SPEC §3.1, "Boundaries"). The particles
are placed by :mod:`partmesh.particle.sph.wall_placement`.

Wall state (every step)
-----------------------
With the skewed kernel ``W_s(r, H) = W(|r|, H) (1 + erf(λ·r/H))``,
``λ = −c n̂_w`` (c = 10), evaluated at ``r = x_w − x_j`` with the fluid
particle's own support ``H_j`` (particle j contributes when
``|x_w − x_j| < H_j``) and ``V_j = m_j/ρ_j``:

.. math::

    \bar φ_w = \frac{Σ_j V_j φ_j W_s}{Σ_j V_j W_s}, \qquad
    \bar x_w = \frac{Σ_j V_j x_j W_s}{Σ_j V_j W_s}, \\
    ∇φ_w = M^{-1} Σ_j V_j (φ_j − \bar φ_w) ∇W_s, \qquad
    M = Σ_j V_j ∇W_s ⊗ (x_j − \bar x_w), \\
    φ_w = \bar φ_w + ∇φ_w · (x_w − \bar x_w)

for ``φ = ρ, p, v_x, v_y`` (``∇W_s`` the gradient with respect to ``r``,
:func:`partmesh.particle.kernels.skewed_grad`; ``M_ab = Σ V ∂_a W_s (x_j − x̄)_b``).
The Shepard value ``φ̄_w`` of a linear field is exact at the kernel centroid
``x̄_w`` (not at ``x_w``: the one-sided, skewed weights put ``x̄_w`` inside
the fluid), and with ``x̄_w`` as the reference point ``Σ V (φ_j − φ̄) ∇W_s
= M ∇φ`` exactly, so value and gradient at ``x_w`` reproduce any linear
field to round-off (first-order consistency). The skewing switches off
fluid particles on the solid side of the wall (the far side of a thin body,
round a sharp apex): their weight falls as ``1 + erf(−10 δ/H)`` with the
depth ``δ`` behind the wall plane.

* ``|det M| ≤ 10⁻⁶ ‖M‖²_F`` (too few or collinear neighbours): zero
  gradient, ``φ_w = φ̄_w``.
* No fluid particle reaches ``w`` (zero total weight): ``φ_w`` is the state
  of the nearest fluid particle, zero gradient.
* Positivity: for ρ and p the correction ``δ`` (centroid → wall) is
  limited to ``−½ φ ≤ δ ≤ φ``, so the corrected value stays within
  ``[½ φ, 2 φ]`` of the value it corrects.

Virtual state (every step)
--------------------------
For the virtual particle ``v`` of anchor ``w`` and offset ``d``, the
Taylor expansion about the wall particle is taken at the virtual particle's
mirror image across the wall's tangent, offset ``d_m = d − 2 (d·n̂_w) n̂_w``
(the fluid state a plane-wall mirror ghost would carry, so the wall is a
symmetry plane of pressure and density to first order):
``ρ_v = ρ_w + ∇ρ_w·d_m``, ``p_v = p_w + ∇p_w·d_m``,
``v_m = v_w + (∇v_w)·d_m`` and the slip-wall mirror about the anchor's
normal ``v_v = v_m − 2 (v_m·n̂_w) n̂_w``, so fluid approaching the wall meets
virtual particles approaching it from the other side; mass
``m_v = ρ_v V_v``, support ``H_v = η √V_v`` and ``u_v = p_v / ((γ − 1) ρ_v)``.

Bounds: ``ρ_v``, ``p_v/ρ_v`` and each component of ``v_m`` are clipped to
the range of that quantity over the fluid particles in front of the anchor
(those reaching it from the fluid side of its tangent, ``(x_j − x_w)·n̂_w ≥
0``; where none is in front, all that reach it), the local-extremum bound of
MUSCL limiters (Barth & Jespersen 1989, AIAA 89-0366) applied to the
extrapolation. Linear ρ, p and v are untouched where the mirror image lies
within the convex hull of those particles (a linear function and a ratio
of two, p/ρ, take their extremes over a convex set at its corners); what
the bounds stop is a wall acting as a source.
Extrapolated apart, ρ and p may each be off by a factor of a few where the
gradients are steep and one-sided (behind the apex of an obstacle in a
strong blast, where the wake is near vacuum), and a virtual particle hotter
than every fluid particle near it heats them (artificial conduction,
compression by virtual velocities far above the fluid's), which raises the
wall state in turn: the run runs away.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import prange
from scipy.spatial import cKDTree

from partmesh.cases.errors import InputError
from partmesh.compare.checks import positive
from partmesh.particle.cell_grid import cell_grid, counting_sort
from partmesh.particle.kernels import kernel_id, skewed_grad, skewed_w
from partmesh.particle.sph.wall_placement import Wall, periodic_images
from partmesh.particle.threads import PRANGE_ONLY

#: c in the skewness λ = −c n̂ (Prasanna Kumar et al. 2018).
SKEW = 10.0

# |det M| below this fraction of ‖M‖²_F counts as singular (zero gradient)
_SINGULAR = 1e-6
# ρ and p (the first two wall fields) are positive and limited
_N_POSITIVE = 2


@numba.njit(cache=True)
def _cell_of(p, origin, width, n):
    c = math.floor((p - origin) / width)
    return min(max(c, 0), n - 1)


@numba.njit(cache=True, parallel=PRANGE_ONLY)
def _support_pass(points, xs, Hs, start, origin, width, ncell, offsets, index, dx, order, fill):
    """Per point, the particles j (cell-sorted ``xs``, ``Hs``) with
    ``|p − x_j| < H_j`` in the 3×3 cells around the point's cell. ``fill``
    False: return the counts; True: write them at ``offsets`` (original ids
    via ``order``, ``dx = p − x_j``)."""
    m = points.shape[0]
    counts = np.zeros(m, dtype=np.int64)
    for k in prange(m):
        px, py = points[k, 0], points[k, 1]
        cx = _cell_of(px, origin[0], width[0], ncell[0])
        cy = _cell_of(py, origin[1], width[1], ncell[1])
        q = offsets[k] if fill else 0
        c = 0
        for yc in range(max(cy - 1, 0), min(cy + 2, ncell[1])):
            row = yc * ncell[0]
            for t in range(start[row + max(cx - 1, 0)], start[row + min(cx + 2, ncell[0])]):
                ex = px - xs[t, 0]
                ey = py - xs[t, 1]
                if ex * ex + ey * ey < Hs[t] * Hs[t]:
                    if fill:
                        index[q + c] = order[t]
                        dx[q + c, 0] = ex
                        dx[q + c, 1] = ey
                    c += 1
        counts[k] = c
    return counts


def points_within_support(points, x, H) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """For every point ``p_k`` (2D), the particles ``j`` with
    ``|p_k − x_j| < H_j`` (each particle's own support), as CSR lists
    ``(offsets, index, dx)``: point k's particles are
    ``index[offsets[k]:offsets[k+1]]``, ``dx = p_k − x_j``.

    Cell list with cells ``≥ max H`` wide over the bounding box of points and
    particles, stable counting sort of the particles (O(N)), 3×3 stencil per
    point: O(N + points · neighbours). No periodic images.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    x = np.ascontiguousarray(x, dtype=np.float64)
    H = np.ascontiguousarray(H, dtype=np.float64)
    m = len(points)
    if m == 0 or len(x) == 0:
        return np.zeros(m + 1, np.int64), np.zeros(0, np.int64), np.zeros((0, 2))
    lo = np.minimum(points.min(axis=0), x.min(axis=0))
    hi = np.maximum(points.max(axis=0), x.max(axis=0))
    origin, width, ncell, _, _ = cell_grid(x, lo, hi, (False, False), float(H.max()))
    cid = (np.clip(np.floor((x[:, 0] - origin[0]) / width[0]), 0, ncell[0] - 1).astype(np.int64)
           + ncell[0] * np.clip(np.floor((x[:, 1] - origin[1]) / width[1]), 0, ncell[1] - 1).astype(np.int64))
    start, order = counting_sort(cid, int(ncell[0] * ncell[1]))
    xs, Hs = x[order], H[order]
    grid = (xs, Hs, start, origin[:2], width[:2], ncell[:2])
    none = np.zeros(0, np.int64)
    counts = _support_pass(points, *grid, none, none, np.zeros((0, 2)), order, False)
    offsets = np.concatenate([[0], np.cumsum(counts)])
    index = np.empty(offsets[-1], dtype=np.int64)
    dx = np.empty((offsets[-1], 2))
    _support_pass(points, *grid, offsets, index, dx, order, True)
    return offsets, index, dx


@numba.njit(cache=True, inline="always")
def _limited(phi, delta):
    """Correction ``delta`` to the positive value ``phi`` clipped to
    ``[−½ phi, phi]`` (no correction if ``phi ≤ 0``)."""
    if phi <= 0.0:
        return 0.0
    return min(max(delta, -0.5 * phi), phi)


@numba.njit(cache=True, inline="always")
def _spanned(state, f):
    """Field ``f`` of the fields a virtual particle is bounded in, ``(ρ, p/ρ,
    v_x, v_y)``, of the fluid state ``(ρ, p, v_x, v_y)``."""
    return state[1] / state[0] if f == 1 else state[f]


@numba.njit(cache=True, inline="always")
def _widen(span, state):
    """Widen the ranges ``span (4, 2)`` of :func:`_spanned`'s fields to hold ``state``."""
    for f in range(span.shape[0]):
        value = _spanned(state, f)
        span[f, 0] = min(span[f, 0], value)
        span[f, 1] = max(span[f, 1], value)


@numba.njit(cache=True, parallel=PRANGE_ONLY)
def _wall_fields(kind, normal, offsets, index, dx, fields, V, H, c):
    """Skewed-kernel Shepard values moved to the wall point with the corrected
    gradient (module docstring); ``reached[w]`` False where the total weight
    is zero (values and gradients then left at 0)."""
    nw = normal.shape[0]
    nf = fields.shape[1]
    value = np.zeros((nw, nf))
    grad = np.zeros((nw, nf, 2))
    reached = np.zeros(nw, dtype=np.bool_)
    span = np.empty((nw, nf, 2))  # per field of _spanned: its range over the fluid in front
    for w in prange(nw):
        lx = -c * normal[w, 0]
        ly = -c * normal[w, 1]
        a, b = offsets[w], offsets[w + 1]
        total = 0.0
        cx = 0.0
        cy = 0.0
        for f in range(nf):
            span[w, f, 0] = np.inf
            span[w, f, 1] = -np.inf
        for q in range(a, b):
            j = index[q]
            wq = V[j] * skewed_w(kind, dx[q, 0], dx[q, 1], H[j], 2, lx, ly)
            total += wq
            cx -= wq * dx[q, 0]  # x_j − x_w = −dx
            cy -= wq * dx[q, 1]
            for f in range(nf):
                value[w, f] += wq * fields[j, f]
            if wq > 0.0 and dx[q, 0] * normal[w, 0] + dx[q, 1] * normal[w, 1] <= 0.0:  # (x_j − x_w)·n̂ ≥ 0
                _widen(span[w], fields[j])
        if not total > 0.0:
            for f in range(nf):
                value[w, f] = 0.0
            continue
        reached[w] = True
        if span[w, 0, 0] > span[w, 0, 1]:  # no fluid in front, only the erf tail behind: its range
            for q in range(a, b):
                _widen(span[w], fields[index[q]])
        cx /= total
        cy /= total
        for f in range(nf):
            value[w, f] /= total
        m00 = 0.0
        m01 = 0.0
        m10 = 0.0
        m11 = 0.0
        for q in range(a, b):
            j = index[q]
            gx, gy = skewed_grad(kind, dx[q, 0], dx[q, 1], H[j], 2, lx, ly)
            gx *= V[j]
            gy *= V[j]
            ex = -dx[q, 0] - cx  # x_j − x̄_w
            ey = -dx[q, 1] - cy
            m00 += gx * ex
            m01 += gx * ey
            m10 += gy * ex
            m11 += gy * ey
            for f in range(nf):
                d = fields[j, f] - value[w, f]
                grad[w, f, 0] += d * gx
                grad[w, f, 1] += d * gy
        det = m00 * m11 - m01 * m10
        if not abs(det) > _SINGULAR * (m00 * m00 + m01 * m01 + m10 * m10 + m11 * m11):
            for f in range(nf):
                grad[w, f, 0] = 0.0
                grad[w, f, 1] = 0.0
            continue
        for f in range(nf):
            b0 = grad[w, f, 0]
            b1 = grad[w, f, 1]
            g0 = (m11 * b0 - m01 * b1) / det
            g1 = (m00 * b1 - m10 * b0) / det
            grad[w, f, 0] = g0
            grad[w, f, 1] = g1
            delta = -(g0 * cx + g1 * cy)  # ∇φ · (x_w − x̄_w)
            value[w, f] += _limited(value[w, f], delta) if f < _N_POSITIVE else delta
    return value, grad, reached, span


def _fluid_arrays(x, v, rho, p, m, H):
    """Validated fluid arrays: positions (n, 2), fields (n, 4) = (ρ, p, v_x,
    v_y), volumes m/ρ and supports H."""
    x = np.asarray(x, dtype=np.float64)
    n = len(x)
    if x.shape != (n, 2) or n == 0:
        raise InputError(f"x must hold the fluid positions with shape (n, 2), n >= 1; got shape {x.shape}.")
    v = np.asarray(v, dtype=np.float64)
    if v.shape != (n, 2):
        raise InputError(f"v must have shape ({n}, 2) like x; got shape {v.shape}.")
    cols = {}
    for name, a in (("rho", rho), ("p", p), ("m", m), ("H", H)):
        a = np.asarray(a, dtype=np.float64)
        if a.shape != (n,):
            raise InputError(f"{name} must have shape ({n},), one value per fluid particle; got {a.shape}.")
        cols[name] = a
    for name in ("rho", "m", "H"):
        if not np.all(cols[name] > 0):
            raise InputError(f"{name} must be > 0 for every fluid particle.")
    fields = np.column_stack([cols["rho"], cols["p"], v])
    return np.ascontiguousarray(x), fields, cols["m"] / cols["rho"], np.ascontiguousarray(cols["H"])


def wall_state(wall, x, v, rho, p, m, H, kind, skew=SKEW) -> tuple[np.ndarray, np.ndarray]:
    """Values ``(n_w, 4)`` and gradients ``(n_w, 4, 2)`` of ``(ρ, p, v_x, v_y)``
    at the wall particles, from the fluid particles ``x (n, 2)``, ``v (n, 2)``,
    ``rho, p, m, H (n,)`` (``H`` the compact support radius): skewed-kernel
    Shepard value and first-order-consistent gradient (module docstring),
    ``gradients[w, f] = ∇φ_f``. ``kind`` is a kernel name or id
    (:data:`partmesh.particle.kernels.KERNELS`); ``skew`` the c of ``λ = −c n̂``
    (0 gives the plain kernel). A wall particle no fluid particle reaches
    takes the state of the nearest fluid particle, with zero gradient.
    """
    return _state_at_walls(wall, x, v, rho, p, m, H, kind, skew)[:2]


def _state_at_walls(wall, x, v, rho, p, m, H, kind, skew):
    """:func:`wall_state`'s values and gradients and ``span (n_w, 4, 2)``,
    the smallest and largest ρ, p/ρ, v_x and v_y of the fluid particles in
    front of each wall particle (on the fluid side of its tangent, within
    their supports; all that reach it where none is in front; the nearest
    one's where none reaches)."""
    if not isinstance(wall, Wall):
        raise InputError("wall must be the Wall returned by walls().")
    kind = kernel_id(kind)
    skew = float(skew)
    if not (math.isfinite(skew) and skew >= 0):
        raise InputError(f"skew must be a finite number >= 0; got {skew!r}.")
    x, fields, V, H = _fluid_arrays(x, v, rho, p, m, H)
    if np.any(wall.period > 0.0):  # the fluid across a periodic side, as its images
        x, source = periodic_images(x, wall.lo, wall.period, float(H.max()))
        fields, V, H = fields[source], V[source], H[source]
    offsets, index, dx = points_within_support(wall.x_wall, x, H)
    value, grad, reached, span = _wall_fields(kind, wall.normal_wall, offsets, index, dx, fields, V, H, skew)
    lost = np.flatnonzero(~reached)
    if lost.size:
        _, j = cKDTree(x).query(wall.x_wall[lost])
        value[lost] = fields[j]
        nearest = fields[j].copy()
        nearest[:, 1] /= nearest[:, 0]
        span[lost] = nearest[:, :, None]
    return value, grad, span


@numba.njit(cache=True, inline="always")
def _clipped(value, bounds):
    """``value`` clipped to ``[bounds[0], bounds[1]]``."""
    return min(max(value, bounds[0]), bounds[1])


@numba.njit(cache=True, parallel=PRANGE_ONLY)
def _extrapolated(value, grad, span, anchor, offset, normal, volume, eta, gamma):
    """Virtual particles' velocity, density, specific energy, support and mass
    by the Taylor expansion about their anchors, evaluated at their mirror
    images (module docstring)."""
    nv = anchor.shape[0]
    vel = np.empty((nv, 2))
    rho = np.empty(nv)
    u = np.empty(nv)
    Hv = np.empty(nv)
    mv = np.empty(nv)
    for i in prange(nv):
        w = anchor[i]
        # the mirror image of the offset across the wall's tangent: d − 2 (d·n̂) n̂
        dn = offset[i, 0] * normal[w, 0] + offset[i, 1] * normal[w, 1]
        d0 = offset[i, 0] - 2.0 * dn * normal[w, 0]
        d1 = offset[i, 1] - 2.0 * dn * normal[w, 1]
        r = _clipped(value[w, 0] + grad[w, 0, 0] * d0 + grad[w, 0, 1] * d1, span[w, 0])
        pv = value[w, 1] + grad[w, 1, 0] * d0 + grad[w, 1, 1] * d1
        vx = _clipped(value[w, 2] + grad[w, 2, 0] * d0 + grad[w, 2, 1] * d1, span[w, 2])
        vy = _clipped(value[w, 3] + grad[w, 3, 0] * d0 + grad[w, 3, 1] * d1, span[w, 3])
        vn = vx * normal[w, 0] + vy * normal[w, 1]
        vel[i, 0] = vx - 2.0 * vn * normal[w, 0]
        vel[i, 1] = vy - 2.0 * vn * normal[w, 1]
        rho[i] = r
        u[i] = _clipped(pv / r, span[w, 1]) / (gamma - 1.0)
        Hv[i] = eta * math.sqrt(volume[i])
        mv[i] = r * volume[i]
    return vel, rho, u, Hv, mv


def virtual_state(wall, x, v, rho, p, m, H, kind, eta, gamma, skew=SKEW):
    """State of the virtual particles from the fluid particles (arguments as
    in :func:`wall_state`; ``eta`` the smoothing factor, ``gamma`` > 1).

    Returns ``(xv, vv, rhov, uv, Hv, mv)``: positions ``(n_v, 2)`` (a copy),
    velocities ``(n_v, 2)``, density, specific internal energy
    ``p_v/((γ−1)ρ_v)``, support ``η √V_v`` and mass ``ρ_v V_v`` (each
    ``(n_v,)``): the Taylor expansion about the anchor wall particle taken
    at the virtual particle's mirror image across the wall's tangent, ρ, p/ρ
    and each velocity component clipped to their range over the fluid in
    front of the anchor (module docstring), the velocity then mirrored about
    the anchor's normal (slip wall).
    """
    eta = positive("eta", eta)
    gamma = positive("gamma", gamma)
    if not gamma > 1.0:
        raise InputError(f"gamma must be > 1; got {gamma:g}.")
    value, grad, span = _state_at_walls(wall, x, v, rho, p, m, H, kind, skew)
    vv, rhov, uv, Hv, mv = _extrapolated(value, grad, span, wall.anchor, wall.offset, wall.normal_wall,
                                         wall.volume, eta, gamma)
    return np.array(wall.x_virtual), vv, rhov, uv, Hv, mv
