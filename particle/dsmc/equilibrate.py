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

from partmesh.particle.dsmc.cells import record_cell_sums
from partmesh.particle.dsmc.profile import redrawn_about_profile
from partmesh.particle.dsmc.random import gamma, normal, stream
from partmesh.particle.threads import PRANGE_ONLY


#: the cells a thread takes at a time
_CELLS = 64


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def equilibrate(x, v, e, start, zeta, seed, step, count, momentum, energy, slopes, due):
    """Redraw, in place, the velocities ``v`` (n, 3) and specific internal
    energies ``e`` (n,) of the particles of every cell with ≥ 2 of them,
    about the cell's mean velocity, or about its linear profile with the
    cell's ``slopes`` (ncell, dim, 4) at the positions ``x``
    (:mod:`partmesh.particle.dsmc.profile`; ``slopes`` of no rows: uniform).

    The particles are in cell order (:func:`partmesh.particle.dsmc.cells.sort_into_cells`):
    cell c holds ``start[c]:start[c+1]``. ``zeta`` ≥ 0 internal degrees of
    freedom (0: ``e`` is left alone). Cell c draws from the stream
    ``(seed, step, c)``, so the result does not depend on the thread count.
    Fills, per cell, ``count`` (N), ``momentum`` (Σ v, (ncell, 3)) and
    ``energy`` (Σ ½|v|² + e): the sums the redraw conserves, of every
    cell, also those ``due`` (ncell,) leaves as they are
    (:mod:`partmesh.particle.dsmc.intervals`; ``due`` of no rows: all
    are redrawn)."""
    ncell = start.size - 1
    for chunk in numba.prange((ncell + _CELLS - 1) // _CELLS):
        _equilibrate_cells(chunk * _CELLS, min(ncell, (chunk + 1) * _CELLS), x, v, e, start, zeta, seed, step,
                           count, momentum, energy, slopes, due)


@numba.njit(cache=True, error_model="numpy")
def _equilibrate_cells(first, end, x, v, e, start, zeta, seed, step, count, momentum, energy, slopes, due):
    """:func:`equilibrate` of the cells ``first:end``."""
    for cell in range(first, end):
        a, b = start[cell], start[cell + 1]
        # the cell's momentum and energy per unit particle mass
        N, p0, p1, p2, total = record_cell_sums(v, e, a, b, zeta, cell, count, momentum, energy)
        if N < 2 or (due.size > 0 and not due[cell]):
            continue
        U0, U1, U2 = p0 / N, p1 / N, p2 / N
        thermal = total - 0.5 * N * (U0 * U0 + U1 * U1 + U2 * U2)
        # the draw c (3 normals per particle) and ε, written in place of v and e
        state, m0, m1, m2, drawn = drawn_deviations(stream(seed, step, cell), v, e, a, b, zeta)
        if slopes.shape[0] > 0:
            redrawn_about_profile(x, v, e, a, b, U0, U1, U2, thermal, 1.0, zeta, slopes, cell)
        else:
            set_about(v, e, a, b, U0, U1, U2, m0, m1, m2, max(thermal, 0.0) / drawn, zeta)


@numba.njit(cache=True, inline="always")
def drawn_deviations(state, v, e, a, b, zeta):
    """Draw into rows ``a:b`` of ``v`` three standard normals c_i each and,
    if ``zeta`` > 0, into ``e`` ε_i ~ Gamma(ζ/2, 1); returns ``(state, c̄₀,
    c̄₁, c̄₂, ½ Σ |c_i − c̄|² + Σ ε_i)``."""
    N = b - a
    m0 = m1 = m2 = 0.0
    squares = 0.0
    for i in range(a, b):
        state, z0 = normal(state)
        state, z1 = normal(state)
        state, z2 = normal(state)
        v[i, 0], v[i, 1], v[i, 2] = z0, z1, z2
        m0 += z0
        m1 += z1
        m2 += z2
        squares += z0 * z0 + z1 * z1 + z2 * z2
        if zeta > 0.0:
            state, eps = gamma(state, 0.5 * zeta)
            e[i] = eps
            squares += 2.0 * eps
    m0, m1, m2 = m0 / N, m1 / N, m2 / N
    return state, m0, m1, m2, 0.5 * (squares - N * (m0 * m0 + m1 * m1 + m2 * m2))


@numba.njit(cache=True, inline="always")
def set_about(v, e, a, b, U0, U1, U2, m0, m1, m2, s2, zeta):
    """Rows ``a:b`` of the draw (:func:`drawn_deviations`, mean ``m``) moved
    to ``v_i = U + s (c_i − c̄)`` and ``e_i = s² ε_i``."""
    s = np.sqrt(s2)
    for i in range(a, b):
        v[i, 0] = U0 + s * (v[i, 0] - m0)
        v[i, 1] = U1 + s * (v[i, 1] - m1)
        v[i, 2] = U2 + s * (v[i, 2] - m2)
        if zeta > 0.0:
            e[i] = s2 * e[i]
