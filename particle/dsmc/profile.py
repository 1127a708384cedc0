"""The mean velocity and temperature the equilibrium redraw draws about,
across a cell.

Pullin's redraw (:mod:`partmesh.particle.dsmc.equilibrate`) gives every
particle of a cell the cell's mean velocity U_c and temperature θ_c, so each
step spreads the cell's momentum and heat evenly over the cell. Beside the
viscosity of the redraw itself (of order p Δt/2) this remap adds one of
order ρ Δx²/Δt, the larger part where the gas is cooler than the hottest,
whose temperature sets Δt. ``profile="linear"`` draws each particle about
the cell's means carried to its place,

    U(x_i) = U_c + G_c (x_i − x̄_c),   θ(x_i) = θ_c + g_c · (x_i − x̄_c),

G_c and g_c the slopes of the cell means, limited by the monotonized central
limiter between the two neighbours along each axis, minmod(2a, 2b, (a + b)/2)
of the backward and forward differences a, b (van Leer 1977, J. Comput.
Phys. 23, 276; zero where a neighbour is missing: an edge that does not wrap,
a cell with fewer than two particles), x̄_c the centroid of the cell's particles (whose
weights w_i are equal when they are redrawn), so that Σ w_i (x_i − x̄_c) = 0.
The draw c_i, ε_i (standard normals, Gamma variates) is scaled to the
local temperature, c_i ← √r_i c_i and ε_i ← r_i ε_i with r_i = θ(x_i)/θ_c
kept in [1/4, 4]; its mean is removed and it is made orthogonal to the
velocity profile P_i = G_c (x_i − x̄_c), c ← c − α P with
α = Σ c_i·P_i / Σ |P_i|². The profile's energy K_c = ½ Σ w_i |P_i|² comes
out of the thermal energy E_th; where it would exceed ½ E_th, the profile is
scaled by f = √(E_th / 2K_c). Then

    v_i = U_c + f P_i + s c_i,   e_i = s² ε_i,
    s² = (E_th − f² K_c) / (½ Σ w_i |c_i|² + Σ w_i ε_i),

keeps the cell's momentum and energy to round-off. θ_c is the heat about
U_c, the profile's energy included, so the temperature the particles carry
is θ(x_i) (E_th − f² K_c)/E_th: the profile's share of the heat (at most
a half, and far less wherever the flow is smooth on the cell) comes out
of the temperature's level and slope alike. It is the particle
counterpart of a MUSCL reconstruction, and of the affine transfer by which
APIC keeps a particle-in-cell method from dissipating its velocity field
(Jiang, Schroeder, Selle, Teran & Stomakhin 2015, ACM Trans. Graph. 34, 51).

The limiter matters where the flow changes little from cell to cell
beside the scatter of the cell means (√(θ/N) in each velocity component,
some 50 m/s in air at 30 a cell): on a weak front spread over ten cells or
more, minmod's smaller difference keeps little of the slope and MC's
central difference much more of it. On ``surface_burst`` in r–z at 4 cm
to 17.5 ms the raw peak overpressure over Kingery–Bulmash at Z2 / Z3 / Z5 /
Z8 reads 0.901 / 0.829 / 0.849 / 0.863 (seed 1) and 0.915 / 0.751 / 0.699 /
0.751 (seed 2) with MC slopes, 0.884 / 0.774 / 0.728 / 0.749 and 0.863 /
0.783 / 0.705 / 0.744 with minmod's: a gain at Z5 and Z8 on the mean of
the two, inside the scatter from seed to seed (the uniform redraw's record
at 4 cm: Z3 / Z5 / Z8 0.725 / 0.763 / 0.655); a smaller or larger step did
not help (minmod slopes to 13 ms: cfl 0.5 and 2 read lower than cfl 1 at
Z2 and Z3). On a 1D Sod tube of 400 cells (3 000 particles a cell), where
the scatter is small, the L1 density error falls from 9.2e-3 (uniform) to
6.2e-3 (6.7e-3 with minmod slopes; first-order EFM finite volumes on the
same cells: 7.5e-3).
"""

from __future__ import annotations

import numba
import numpy as np

from partmesh.particle.dsmc.cells import weighted_sums
from partmesh.particle.threads import PRANGE_ONLY

#: the mean-velocity profiles of the redraw
PROFILES = ("uniform", "linear")
#: slopes that say "uniform": no cell has a row (the kernels take this in place of (ncell, dim, 4))
NO_SLOPES = np.zeros((0, 1, 4))
#: the largest share of a cell's thermal energy its velocity profile may take
MAX_PROFILE_SHARE = 0.5
#: a velocity profile of less energy than this share of the heat is left out (its direction is round-off)
NEGLIGIBLE_PROFILE = 1e-24
#: the temperature profile's bounds on θ(x_i)/θ_c: [this, 1/this]
MIN_TEMPERATURE_RATIO = 0.25


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def cell_means(v, e, w, start, zeta):
    """Per cell (cell c holds ``start[c]:start[c+1]``): the particle count
    and the means (ncell, 4) U = Σ w v / Σ w (three components) and
    θ = 2 E_th / ((3 + ζ) Σ w), E_th = Σ w (½|v − U|² + e) (``e`` counted if
    ``zeta`` > 0); ``w`` empty means equal weights. A cell without
    particles has means 0."""
    ncell = start.size - 1
    count = np.empty(ncell, dtype=np.int64)
    mean = np.zeros((ncell, 4))
    for c in numba.prange(ncell):
        a, b = start[c], start[c + 1]
        count[c] = b - a
        S, p0, p1, p2, total = weighted_sums(v, e, w, a, b, zeta)
        if S > 0.0:
            U0, U1, U2 = p0 / S, p1 / S, p2 / S
            thermal = total - 0.5 * S * (U0 * U0 + U1 * U1 + U2 * U2)
            mean[c, 0], mean[c, 1], mean[c, 2] = U0, U1, U2
            mean[c, 3] = max(thermal, 0.0) / (0.5 * (3.0 + zeta) * S)
    return count, mean


def limited_slopes(count, mean, shape, spacing, periodic) -> np.ndarray:
    """The MC-limited slopes ∂q/∂x_a of the cell means ``mean`` (ncell,
    4: U and θ, :func:`cell_means`) on the grid of ``shape`` (cells per
    axis, x fastest) and ``spacing``; an axis wraps where ``periodic[a]``.
    Cells with ``count`` < 2 give no slope and serve as no neighbour.
    Returns (ncell, dim, 4)."""
    return _slopes_on_grid(np.ascontiguousarray(count, dtype=np.int64), np.ascontiguousarray(mean, dtype=float),
                           np.asarray(shape, dtype=np.int64), np.asarray(spacing, dtype=float),
                           np.asarray(periodic, dtype=np.bool_))


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def _slopes_on_grid(count, mean, shape, spacing, periodic):
    """:func:`limited_slopes`, cell by cell: along axis a, cell c's
    neighbours are c ± stride_a, wrapped across the edge where the axis is
    periodic."""
    dim = shape.size
    slopes = np.zeros((count.size, dim, 4))
    for c in numba.prange(count.size):
        if count[c] < 2:
            continue
        stride = 1
        for a in range(dim):
            n = shape[a]
            i = (c // stride) % n
            ahead = c + stride if i + 1 < n else (c - (n - 1) * stride if periodic[a] else -1)
            behind = c - stride if i > 0 else (c + (n - 1) * stride if periodic[a] else -1)
            if ahead >= 0 and behind >= 0 and count[ahead] >= 2 and count[behind] >= 2:
                for q in range(4):
                    slopes[c, a, q] = monotonized_central(mean[c, q] - mean[behind, q],
                                                          mean[ahead, q] - mean[c, q]) / spacing[a]
            stride *= n
    return slopes


@numba.njit(cache=True, inline="always")
def monotonized_central(a, b):
    """The MC limiter of backward and forward differences ``a``, ``b``:
    minmod(2a, 2b, (a + b)/2), zero where their signs differ (van Leer 1977)."""
    if not a * b > 0.0:
        return 0.0
    central = 0.5 * (a + b)
    return np.sign(central) * min(abs(central), 2.0 * min(abs(a), abs(b)))


@numba.njit(cache=True, inline="always")
def centroid(x, a, b):
    """x̄ of the rows ``a:b`` of ``x``: ``(x̄₀, x̄₁)``, x̄₁ = 0 in 1D."""
    xb0 = xb1 = 0.0
    for i in range(a, b):
        xb0 += x[i, 0]
        if x.shape[1] > 1:
            xb1 += x[i, 1]
    return xb0 / (b - a), xb1 / (b - a)


@numba.njit(cache=True, inline="always")
def profile_at(x, i, slopes, cell, xb0, xb1, q):
    """G_c (x_i − x̄_c) of quantity ``q`` (0–2: U, 3: θ) of the cell's ``slopes``."""
    change = slopes[cell, 0, q] * (x[i, 0] - xb0)
    if x.shape[1] > 1:
        change += slopes[cell, 1, q] * (x[i, 1] - xb1)
    return change


@numba.njit(cache=True, inline="always")
def velocity_profile_at(x, i, slopes, cell, xb0, xb1):
    """P_i = G_c (x_i − x̄_c), three components."""
    return (profile_at(x, i, slopes, cell, xb0, xb1, 0), profile_at(x, i, slopes, cell, xb0, xb1, 1),
            profile_at(x, i, slopes, cell, xb0, xb1, 2))


@numba.njit(cache=True, inline="always")
def redrawn_about_profile(x, v, e, a, b, U0, U1, U2, thermal, weight, zeta, slopes, cell):
    """Rows ``a:b`` of a fresh draw (:func:`~partmesh.particle.dsmc.equilibrate.drawn_deviations`:
    standard normals in ``v``, Gamma variates in ``e``) set to
    ``v_i = U + f P_i + s c_i`` and ``e_i = s² ε_i``, the draw scaled to the
    temperature profile, its mean removed and made orthogonal to P, for
    particles of equal ``weight`` holding ``thermal`` energy in the cell's
    frame (module docstring)."""
    N = b - a
    xb0, xb1 = centroid(x, a, b)
    theta = max(thermal, 0.0) / (0.5 * (3.0 + zeta) * weight * N)
    # the draw at the temperature θ(x_i)/θ_c of each particle's place
    m0 = m1 = m2 = squares = 0.0
    for i in range(a, b):
        ratio = 1.0 + profile_at(x, i, slopes, cell, xb0, xb1, 3) / theta if theta > 0.0 else 1.0
        ratio = min(max(ratio, MIN_TEMPERATURE_RATIO), 1.0 / MIN_TEMPERATURE_RATIO)
        scale = np.sqrt(ratio)
        v[i, 0], v[i, 1], v[i, 2] = scale * v[i, 0], scale * v[i, 1], scale * v[i, 2]
        m0 += v[i, 0]
        m1 += v[i, 1]
        m2 += v[i, 2]
        squares += v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        if zeta > 0.0:
            e[i] = ratio * e[i]
            squares += 2.0 * e[i]
    m0, m1, m2 = m0 / N, m1 / N, m2 / N
    drawn = 0.5 * (squares - N * (m0 * m0 + m1 * m1 + m2 * m2))
    # the velocity profile P, its energy and its overlap with the draw
    half_squares = crossed = 0.0
    for i in range(a, b):
        P0, P1, P2 = velocity_profile_at(x, i, slopes, cell, xb0, xb1)
        half_squares += 0.5 * (P0 * P0 + P1 * P1 + P2 * P2)
        crossed += (v[i, 0] - m0) * P0 + (v[i, 1] - m1) * P1 + (v[i, 2] - m2) * P2
    f = alpha = 0.0
    if thermal > 0.0 and weight * half_squares > NEGLIGIBLE_PROFILE * thermal:
        share = weight * half_squares / thermal
        f = 1.0 if share <= MAX_PROFILE_SHARE else np.sqrt(MAX_PROFILE_SHARE / share)
        alpha = crossed / (2.0 * half_squares)
        # ½ Σ |c − c̄ − α P|² + Σ ε summed anew: from ½ Σ |c − c̄|² − ½ α Σ c·P it cancels where c lies along P
        drawn = 0.0
        for i in range(a, b):
            P0, P1, P2 = velocity_profile_at(x, i, slopes, cell, xb0, xb1)
            d0, d1, d2 = v[i, 0] - m0 - alpha * P0, v[i, 1] - m1 - alpha * P1, v[i, 2] - m2 - alpha * P2
            drawn += 0.5 * (d0 * d0 + d1 * d1 + d2 * d2)
            if zeta > 0.0:
                drawn += e[i]
    s2 = max(thermal - f * f * weight * half_squares, 0.0) / (weight * drawn) if drawn > 0.0 else 0.0
    s = np.sqrt(s2)
    beta = f - s * alpha
    for i in range(a, b):
        P0, P1, P2 = velocity_profile_at(x, i, slopes, cell, xb0, xb1)
        v[i, 0] = U0 + s * (v[i, 0] - m0) + beta * P0
        v[i, 1] = U1 + s * (v[i, 1] - m1) + beta * P1
        v[i, 2] = U2 + s * (v[i, 2] - m2) + beta * P2
        if zeta > 0.0:
            e[i] = s2 * e[i]
