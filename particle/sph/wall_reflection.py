"""The safeguard that no gas SPH particle ends a step inside a solid: a
particle found inside an obstacle is mirrored across its surface (SPEC
§3.1, "Boundaries")."""

from __future__ import annotations

import numpy as np

from partmesh.cases.errors import InputError
from partmesh.cases.shapes import Shape

#: mirror passes before reflect_into_fluid falls back to the surface point
_REFLECT_PASSES = 4


def _inside(shapes, x, idx):
    """``(particles, phi, shape)`` for the particles of ``idx`` strictly inside
    a shape (one shape each: the one nearest its surface). Candidates are
    sorted by x once, each shape tests only those in its bounding box."""
    bounds = np.array([s.bounds() for s in shapes])
    px, py = x[idx, 0], x[idx, 1]
    near = (px >= bounds[:, 0].min()) & (px <= bounds[:, 2].max())
    near &= (py >= bounds[:, 1].min()) & (py <= bounds[:, 3].max())
    idx = idx[near]
    idx = idx[np.argsort(x[idx, 0], kind="stable")]
    xs = x[idx, 0]
    found, phis, which = [], [], []
    for k, s in enumerate(shapes):
        x0, y0, x1, y1 = bounds[k]
        cand = idx[np.searchsorted(xs, x0, "left"):np.searchsorted(xs, x1, "right")]
        cand = cand[(x[cand, 1] >= y0) & (x[cand, 1] <= y1)]
        phi = s.signed_distance(x[cand, 0], x[cand, 1])
        hit = phi < 0.0
        found.append(cand[hit])
        phis.append(phi[hit])
        which.append(np.full(int(hit.sum()), k))
    j, phi, k = np.concatenate(found), np.concatenate(phis), np.concatenate(which)
    order = np.lexsort((-phi, j))  # per particle, the shallowest shape first
    j, phi, k = j[order], phi[order], k[order]
    first = np.ones(len(j), dtype=bool)
    first[1:] = j[1:] != j[:-1]
    return j[first], phi[first], k[first]


def reflect_into_fluid(shapes, x, *velocities):
    """Put every particle inside an obstacle (``φ < 0``) back at its mirror
    image across the surface, ``x − 2 φ n̂``, and reverse the normal
    component of each of its ``velocities`` that points into the solid
    (``v·n̂ < 0``: ``v − 2 (v·n̂) n̂``).

    ``shapes`` is one :class:`partmesh.cases.shapes.Shape` or a sequence of them,
    ``x`` and every velocity array are ``(n, 2)``. Returns ``(x, *velocities,
    count)``: the inputs themselves when no particle was inside, new arrays
    otherwise (the inputs are never modified), and the number of particles
    moved. A mirror image that lands in another (nearby) obstacle is
    mirrored again; after 4 passes any particle still inside is put just
    outside its closest surface point, so no particle is left inside a solid.
    """
    shapes = [shapes] if isinstance(shapes, Shape) else list(shapes)
    if any(not isinstance(s, Shape) for s in shapes):
        raise InputError("shapes must be a partmesh.cases.shapes.Shape or a sequence of them.")
    x_in = np.asarray(x, dtype=np.float64)
    n = len(x_in)
    if x_in.shape != (n, 2):
        raise InputError(f"x must have shape (n, 2) (obstacles are 2D); got shape {x_in.shape}.")
    v_in = [np.asarray(v, dtype=np.float64) for v in velocities]
    if any(v.shape != (n, 2) for v in v_in):
        raise InputError(f"every velocity must have shape ({n}, 2) like x.")
    if not shapes or n == 0:
        return (x, *velocities, 0)
    x_out, v_out = None, None
    moved = np.zeros(n, dtype=bool)
    todo = np.arange(n)
    for attempt in range(_REFLECT_PASSES + 1):
        j, phi, k = _inside(shapes, x_in if x_out is None else x_out, todo)
        if j.size == 0:
            break
        if x_out is None:
            x_out, v_out = x_in.copy(), [v.copy() for v in v_in]
        moved[j] = True
        for kk in np.unique(k):
            sel = k == kk
            jj, ph = j[sel], phi[sel]
            nx, ny = shapes[kk].normal(x_out[jj, 0], x_out[jj, 1])
            if attempt < _REFLECT_PASSES:
                x_out[jj, 0] -= 2.0 * ph * nx
                x_out[jj, 1] -= 2.0 * ph * ny
            else:  # last resort: just outside the closest surface point
                eps = 1e-9 * shapes[kk].length_scale()
                x_out[jj, 0] += (eps - ph) * nx
                x_out[jj, 1] += (eps - ph) * ny
            for v in v_out:
                vn = v[jj, 0] * nx + v[jj, 1] * ny
                flip = np.where(vn < 0.0, 2.0 * vn, 0.0)
                v[jj, 0] -= flip * nx
                v[jj, 1] -= flip * ny
        todo = j
    if x_out is None:
        return (x, *velocities, 0)
    return (x_out, *v_out, int(moved.sum()))
