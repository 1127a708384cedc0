"""Free flight of DSMC particles in the scene's box (SPEC §3.3).

Each particle moves in a straight line for dt. At a reflecting side it is
reflected specularly — the normal position and velocity mirrored, exactly,
as many times as it crosses a side in the step — and the momentum it hands
to the side, 2 m |v_n| per bounce, is summed; on a periodic axis it wraps;
through an open side (inflow or outflow) it leaves the run.
"""

from __future__ import annotations

import numba
import numpy as np

from partmesh.particle.threads import PRANGE_ONLY

#: how a side treats a particle that reaches it
REFLECT, PERIODIC, OPEN = 0, 1, 2


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def free_flight(x, v, dt, lo, hi, sides, w=None):
    """Move particles ``x`` (n, dim) with velocities ``v`` (n, 3) for ``dt``,
    in place, in the box ``[lo, hi]``; ``sides`` (2·dim,) holds REFLECT,
    PERIODIC or OPEN for x_lo, x_hi, y_lo, y_hi.

    Returns ``(gone, delivered)``: the particles that left through an open
    side, and per side the momentum per unit particle mass handed to it
    (Σ 2 |v_n| over the bounces, each times the particle's weight ``w`` if
    given; a force once multiplied by the particle mass and divided by dt)."""
    n, dim = x.shape
    gone = np.zeros(n, dtype=np.bool_)
    delivered = np.zeros(2 * dim)
    for a in range(dim):
        lo_a, hi_a = lo[a], hi[a]
        width = hi_a - lo_a
        kind_lo, kind_hi = sides[2 * a], sides[2 * a + 1]
        to_lo = 0.0
        to_hi = 0.0
        for i in numba.prange(n):
            if gone[i]:
                continue
            xa = x[i, a] + dt * v[i, a]
            va = v[i, a]
            while xa < lo_a or xa > hi_a:
                if xa < lo_a:
                    if kind_lo == REFLECT:
                        xa = 2.0 * lo_a - xa
                        to_lo += 2.0 * abs(va) * (1.0 if w is None else w[i])
                        va = -va
                    elif kind_lo == PERIODIC:
                        xa += width
                    else:
                        gone[i] = True
                        break
                else:
                    if kind_hi == REFLECT:
                        xa = 2.0 * hi_a - xa
                        to_hi += 2.0 * abs(va) * (1.0 if w is None else w[i])
                        va = -va
                    elif kind_hi == PERIODIC:
                        xa -= width
                    else:
                        gone[i] = True
                        break
            if kind_hi == PERIODIC and xa == hi_a:
                xa = lo_a  # the periodic box is [lo, hi)
            x[i, a] = xa
            v[i, a] = va
        delivered[2 * a] = to_lo
        delivered[2 * a + 1] = to_hi
    return gone, delivered
