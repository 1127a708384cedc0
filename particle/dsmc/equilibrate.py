"""The equilibrium collision step of Pullin-style DSMC (Pullin 1980,
J. Comput. Phys. 34, 231; Sharma & Long 2003, J. Comput. Phys. 200, 711):
in every cell with at least two particles all velocities and internal
energies are redrawn from the local equilibrium, then corrected so that the
cell's momentum and total energy are exactly those before.

Per cell, for N equal-weight particles with velocities v_i (three
components) and specific internal energies e_i (ζ internal degrees of
freedom; γ = (5 + ζ)/(3 + ζ)):

    U = (1/N) Σ v_i,   E_th = Σ (½|v_i|² + e_i) − ½ N |U|² = N (3 + ζ)/2 θ,

θ = kT/m. Draw c_i ~ N(0, 1)³ and ε_i ~ Gamma(ζ/2, 1), remove the sample
mean c̄, and scale both parts by one factor,

    s² = E_th / (½ Σ |c_i − c̄|² + Σ ε_i),
    v_i ← U + s (c_i − c̄),   e_i ← s² ε_i,

so Σ v_i = N U and Σ (½|v_i|² + e_i) = ½ N |U|² + E_th to round-off, and
the velocities are Maxwellian at (U, θ) and the internal energies
Gamma(ζ/2, θ) up to the O(1/N) correlation the constraint imposes. The
common factor leaves the split between translational and internal energy to
the draw, as in equilibrium.
"""

from __future__ import annotations

import numba
import numpy as np

from particle.dsmc.random import gamma, normal_pair, stream


@numba.njit(parallel=True, cache=True)
def equilibrate(v, e, start, order, zeta, seed, step):
    """Redraw, in place, the velocities ``v`` (n, 3) and specific internal
    energies ``e`` (n,) of the particles of every cell with ≥ 2 of them.

    ``start``/``order`` are a cell sort (:func:`particle.neighbours.counting_sort`):
    cell c holds the particles ``order[start[c]:start[c+1]]``. ``zeta`` ≥ 0
    internal degrees of freedom (0: ``e`` is left alone). Cell c draws from
    the stream ``(seed, step, c)``, so the result does not depend on the
    thread count. Returns the number of cells redrawn."""
    ncell = start.size - 1
    redrawn = np.zeros(ncell, dtype=np.int64)
    for cell in numba.prange(ncell):
        a, b = start[cell], start[cell + 1]
        N = b - a
        if N < 2:
            continue
        # the cell's momentum and energy per unit particle mass
        p0 = p1 = p2 = 0.0
        energy = 0.0
        for k in range(a, b):
            i = order[k]
            p0 += v[i, 0]
            p1 += v[i, 1]
            p2 += v[i, 2]
            energy += 0.5 * (v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2])
            if zeta > 0.0:
                energy += e[i]
        U0, U1, U2 = p0 / N, p1 / N, p2 / N
        thermal = energy - 0.5 * N * (U0 * U0 + U1 * U1 + U2 * U2)
        # the draw, in the cell's own scratch: c (3 per particle) and ε
        state = stream(seed, step, cell)
        c = np.empty((N, 3))
        eps = np.zeros(N)
        for k in range(N):
            state, z0, z1 = normal_pair(state)
            state, z2, _ = normal_pair(state)
            c[k, 0], c[k, 1], c[k, 2] = z0, z1, z2
            if zeta > 0.0:
                state, eps[k] = gamma(state, 0.5 * zeta)
        m0 = c[:, 0].sum() / N
        m1 = c[:, 1].sum() / N
        m2 = c[:, 2].sum() / N
        drawn = 0.0
        for k in range(N):
            c[k, 0] -= m0
            c[k, 1] -= m1
            c[k, 2] -= m2
            drawn += 0.5 * (c[k, 0] * c[k, 0] + c[k, 1] * c[k, 1] + c[k, 2] * c[k, 2]) + eps[k]
        s2 = max(thermal, 0.0) / drawn
        s = np.sqrt(s2)
        for k in range(N):
            i = order[a + k]
            v[i, 0] = U0 + s * c[k, 0]
            v[i, 1] = U1 + s * c[k, 1]
            v[i, 2] = U2 + s * c[k, 2]
            if zeta > 0.0:
                e[i] = s2 * eps[k]
        redrawn[cell] = 1
    return redrawn.sum()
