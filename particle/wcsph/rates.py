r"""Rates of change of weakly compressible water SPH particles (SPEC §3.2;
Monaghan 1994, J. Comput. Phys. 110, 399; Crespo et al. 2015, DualSPHysics,
Comput. Phys. Commun. 187, 204; Fourtakas et al. 2019, Comput. Fluids 190, 346).

Continuity with the δ-SPH density diffusion of Antuono et al. (2010,
Comput. Phys. Commun. 181, 532; Marrone et al. 2011, CMAME 200, 1526),
applied, as Fourtakas et al. (2019) do, to the departure ρ^D = ρ − ρ_H(z)
from the hydrostatic density:

.. math::

    \frac{dρ_a}{dt} = Σ_b m_b\, v_{ab}·∇_a W_{ab}
        + δ h c_0 Σ_b V_b\, \bigl[2(ρ^D_a − ρ^D_b) − (G_a + G_b)·r_{ab}\bigr] \frac{∂W/∂r}{r_{ab}},

with G the renormalised gradient of ρ^D (Randles & Libersky 1996),

.. math::

    G_a = L_a Σ_b V_b (ρ^D_b − ρ^D_a) ∇_a W_{ab}, \qquad
    L_a = \Bigl[Σ_b V_b\, (r_b − r_a) ⊗ ∇_a W_{ab}\Bigr]^{-1},

exact for a linear field even where the kernel is cut by the free surface,
so the term vanishes for a linear ρ^D there too (the plain Molteni &
Colagrossi 2009 term does not, and feeds a steady density flux at the
surface of water at rest),

momentum with the Monaghan viscosity (gravity added by the caller):

.. math::

    \frac{dv_a}{dt} = −Σ_b m_b \Bigl(\frac{P_a}{ρ_a^2} + \frac{P_b}{ρ_b^2} + Π_{ab}\Bigr) ∇_a W_{ab},
    \qquad Π_{ab} = −\frac{α\, \bar c_{ab}\, μ_{ab}}{\bar ρ_{ab}}\ (v_{ab}·r_{ab} < 0),
    \qquad μ_{ab} = \frac{h\, v_{ab}·r_{ab}}{r_{ab}^2 + 0.01h^2},

with V_b = m_b/ρ_b, h = H/2 (the SPEC's q = r/h ≤ 2 of the quintic
Wendland kernel), the sound speed c = c_0 (ρ/ρ_0)³ of the Tait equation and
∇_a W_ab = (∂W/∂r) r_ab/r_ab.
"""

from __future__ import annotations

import numba
import numpy as np

from partmesh.particle.kernels import SIGMA, shape_derivative
from partmesh.particle.pair_geometry import FASTMATH, separation
from partmesh.particle.threads import PRANGE_ONLY

#: a renormalisation matrix whose determinant is below this fraction of (trace/2)² (particles with
#: neighbours on a line only) gives no gradient
SINGULAR = 1e-3


@numba.njit(cache=True, inline="always")
def _add_moments(row, volume, s00, s01, s11, jump, d0, d1):
    """Add one neighbour's share, weighted by its ``volume``, to a particle's
    renormalisation moments (s00, s01, s11) and density-gradient sums
    (``jump`` times the separation ``d``)."""
    row[0] += volume * s00
    row[1] += volume * s01
    row[2] += volume * s11
    row[3] += volume * jump * d0
    row[4] += volume * jump * d1


@numba.njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def _chunk_gradient_sums(first, end, x, box, half, volume, rho_dynamic, H2, inv_H, grad_scale, offsets, index, kind,
                         n, out):
    """Adds the pair terms of the rows ``first:end`` to ``out`` (M00, M01,
    M11, g0, g1 per particle) as :func:`dynamic_density_gradients` describes."""
    for a in range(first, end):
        for k in range(offsets[a], offsets[a + 1]):
            b = index[k]
            if b < a:
                continue
            d0, d1, _, r2 = separation(x, a, b, box, half)
            if r2 >= H2 or r2 <= 0.0:
                continue
            r = np.sqrt(r2)
            Fr = grad_scale * shape_derivative(kind, r * inv_H) / r
            # M += V (r_b − r_a) ⊗ ∇_a W = −V Fr d ⊗ d;  g += V (ρ_b − ρ_a) ∇_a W = V (ρ_b − ρ_a) Fr d
            s00, s01, s11 = -Fr * d0 * d0, -Fr * d0 * d1, -Fr * d1 * d1
            jump = (rho_dynamic[b] - rho_dynamic[a]) * Fr
            _add_moments(out[a], volume[b], s00, s01, s11, jump, d0, d1)
            if b < n:
                _add_moments(out[b], volume[a], s00, s01, s11, jump, d0, d1)


@numba.njit(parallel=PRANGE_ONLY, cache=True, fastmath=FASTMATH, error_model="numpy")
def dynamic_density_gradients(x, box, half, volume, rho_dynamic, H, offsets, index, kind, n, chunks):
    """The renormalised gradient G (n, 2) of ρ^D for the first ``n``
    particles of the 2D set ``x`` (N, 3) (the ghosts after them only serve
    as neighbours); zero where the renormalisation matrix is singular. Pairs
    and blocks as in :func:`rates`."""
    H2 = H * H
    inv_H = 1.0 / H
    grad_scale = SIGMA[kind, 2] * inv_H ** 3
    nchunk = max(1, min(chunks, n))
    # per block and particle: M00, M01, M11, g0, g1
    acc = np.zeros((nchunk, n, 5))
    for ch in numba.prange(nchunk):
        _chunk_gradient_sums(ch * n // nchunk, (ch + 1) * n // nchunk, x, box, half, volume, rho_dynamic, H2, inv_H,
                             grad_scale, offsets, index, kind, n, acc[ch])
    G = np.zeros((n, 2))
    for a in numba.prange(n):
        M = np.zeros(5)
        for ch in range(nchunk):
            for q in range(5):
                M[q] += acc[ch, a, q]
        det = M[0] * M[2] - M[1] * M[1]
        half_trace = 0.5 * (M[0] + M[2])
        if det > SINGULAR * half_trace * half_trace:
            G[a, 0] = (M[2] * M[3] - M[1] * M[4]) / det
            G[a, 1] = (M[0] * M[4] - M[1] * M[3]) / det
    return G


@numba.njit(cache=True, fastmath=FASTMATH, error_model="numpy")
def _chunk_rates(first, end, x, box, half, v, m, rho, c, rho_dynamic, G, p_term, volume, h, eps2, H2, inv_H,
                 grad_scale, diffusion, alpha, offsets, index, kind, n, out):
    """Adds the pair terms of the rows ``first:end`` to ``out`` (a0, a1, a2,
    drho, mu_max per particle) as :func:`rates` describes; returns the
    ordered pairs summed."""
    pairs = 0
    for a in range(first, end):
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        drho = 0.0
        mu_a = 0.0
        for k in range(offsets[a], offsets[a + 1]):
            b = index[k]
            if b < a:
                continue  # evaluated in row b
            d0, d1, d2, r2 = separation(x, a, b, box, half)
            if r2 >= H2 or r2 <= 0.0:
                continue
            r = np.sqrt(r2)
            F = grad_scale * shape_derivative(kind, r * inv_H)  # ∂W/∂r
            Fr = F / r
            dv0 = v[a, 0] - v[b, 0]
            dv1 = v[a, 1] - v[b, 1]
            dv2 = v[a, 2] - v[b, 2]
            vr = dv0 * d0 + dv1 * d1 + dv2 * d2  # v_ab · r_ab
            g = p_term[a] + p_term[b]
            mu = h * vr / (r2 + eps2)
            if vr < 0.0:
                g -= alpha * 0.5 * (c[a] + c[b]) * mu * 2.0 / (rho[a] + rho[b])
            mu_a = max(mu_a, abs(mu))
            # ∇_a W = Fr r_ab; v_ab·∇_a W = Fr vr
            div = Fr * vr
            jump = 2.0 * (rho_dynamic[a] - rho_dynamic[b]) - (
                (G[a, 0] + G[b, 0]) * d0 + (G[a, 1] + G[b, 1]) * d1 + (G[a, 2] + G[b, 2]) * d2)
            diff = diffusion * jump * Fr
            mb = m[b]
            f = mb * g * Fr
            a0 -= f * d0
            a1 -= f * d1
            a2 -= f * d2
            drho += mb * div + volume[b] * diff
            pairs += 1
            if b >= n:
                continue  # a ghost: its rates are not needed
            ma = m[a]
            f = ma * g * Fr
            out[b, 0] += f * d0
            out[b, 1] += f * d1
            out[b, 2] += f * d2
            out[b, 3] += ma * div - volume[a] * diff
            out[b, 4] = max(out[b, 4], abs(mu))
            pairs += 1
        out[a, 0] += a0
        out[a, 1] += a1
        out[a, 2] += a2
        out[a, 3] += drho
        out[a, 4] = max(out[a, 4], mu_a)
    return pairs


@numba.njit(parallel=PRANGE_ONLY, cache=True, fastmath=FASTMATH, error_model="numpy")
def rates(x, box, half, v, m, rho, p, c, rho_dynamic, G, H, c0, alpha, delta, offsets, index, kind, dim, n,
          chunks):
    """``(dvdt, drhodt, mu_max, interactions)`` for the first ``n``
    particles (the fluid; the ghosts after them only serve as neighbours),
    all of support ``H``: the acceleration without gravity (n, dim), the
    density rate, the largest |μ_ab| each particle sees (for the time step)
    and the number of ordered pairs (a fluid, b) with r_ab < H summed.

    ``x`` and ``v`` are (N, 3) (:func:`partmesh.particle.pair_geometry.padded`),
    ``rho_dynamic`` is ρ − ρ_H and ``G`` (N, 3) its renormalised gradient
    (:func:`dynamic_density_gradients`; mirrored for the ghosts). As :func:`partmesh.particle.sph.forces.rates`: each
    fluid–fluid pair is evaluated once, in the row of its smaller index, and
    every one of ``chunks`` contiguous blocks of rows scatters into its own
    accumulators, summed in block order (no races, the same result from run
    to run)."""
    N = x.shape[0]
    p_term = np.empty(N)
    volume = np.empty(N)
    for j in numba.prange(N):
        p_term[j] = p[j] / (rho[j] * rho[j])
        volume[j] = m[j] / rho[j]
    h = 0.5 * H
    eps2 = 0.01 * h * h
    H2 = H * H
    inv_H = 1.0 / H
    grad_scale = SIGMA[kind, dim] * inv_H ** (dim + 1)
    diffusion = delta * h * c0
    nchunk = max(1, min(chunks, n))
    # per block and particle: a0, a1, a2, drho, mu_max
    acc = np.zeros((nchunk, n, 5))
    counted = np.zeros(nchunk, dtype=np.int64)
    for ch in numba.prange(nchunk):
        counted[ch] = _chunk_rates(ch * n // nchunk, (ch + 1) * n // nchunk, x, box, half, v, m, rho, c, rho_dynamic,
                                   G, p_term, volume, h, eps2, H2, inv_H, grad_scale, diffusion, alpha, offsets,
                                   index, kind, n, acc[ch])
    dvdt = np.empty((n, dim))
    drhodt = np.empty(n)
    mu_max = np.empty(n)
    for a in numba.prange(n):
        for q in range(4):
            total = 0.0
            for ch in range(nchunk):
                total += acc[ch, a, q]
            if q < dim:
                dvdt[a, q] = total
            elif q == 3:
                drhodt[a] = total
        largest = 0.0
        for ch in range(nchunk):
            largest = max(largest, acc[ch, a, 4])
        mu_max[a] = largest
    interactions = 0  # (a loop: counted.sum() would compile numpy's sum for this kernel alone)
    for ch in range(nchunk):
        interactions += counted[ch]
    return dvdt, drhodt, mu_max, interactions
