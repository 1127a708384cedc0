"""Equilibrium DSMC in the r–z plane of an axisymmetric scene (Bird 1994,
*Molecular Gas Dynamics and the Direct Simulation of Gas Flows*, §15.1–15.2).

A particle sits at (r, z) and moves with three velocity components
``(v_r, v_z, v_θ)`` (the schema's u, v and the unresolved third). Its free
flight is the straight line of the 3D molecule: from (r, 0) in the plane
normal to the axis it reaches ``(X, Y) = (r + v_r Δt, v_θ Δt)``, and is
rotated back into the meridian plane,

    r' = √(X² + Y²),   v_r' = (X v_r + Y v_θ)/r',   v_θ' = (X v_θ − Y v_r)/r',

reflected specularly off a reflecting outer cylinder r = R where the line
crosses it; the axis is not a wall (molecules pass it). Along z the flight
is the planar one (:func:`~partmesh.particle.dsmc.move.free_flight`).

Radial weighting: a particle stands for ``w`` units of mass ``m``, so that a
ring cell far from the axis, of volume ``V = 2π r_c Δr Δz``, holds no more
particles than one next to it. New gas (the initial fill, the reservoirs of
open sides) is placed uniformly over the r–z plane with ``w = 2 r/Δr``,
which makes its mass density uniform in volume; a cell's target weight is
``w_c = 2 r_c/Δr`` (= 2i + 1 in column i), so a uniform gas has the same
count in every cell. The cloning and removal of particles crossing weight
zones happen in the redraw (:func:`resampled_redraw`): each cell's
particles, of whatever weights, give way to ``M = max(2, round(Σw/w_c))``
particles of the equal weight ``Σw/M``, at positions resampled from the old
ones in proportion to their weights (systematic resampling with a random
offset, which is unbiased: each old particle is copied w/(Σw/M) times on
average, whatever its place in the cell's order), with velocities
and internal energies drawn from the local equilibrium and corrected, as in
:mod:`~partmesh.particle.dsmc.equilibrate`, so that the cell's mass,
momentum and energy are exactly those before.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from partmesh.particle.dsmc.cells import particle_buffers, weighted_sums
from partmesh.particle.dsmc.equilibrate import drawn_deviations, set_about
from partmesh.particle.dsmc.intervals import EVERY_CELL
from partmesh.particle.dsmc.move import REFLECT
from partmesh.particle.dsmc.profile import NO_SLOPES, redrawn_about_profile
from partmesh.particle.dsmc.random import stream, uniform
from partmesh.particle.threads import PRANGE_ONLY

#: bounces off the outer cylinder followed within one step (a molecule grazing it)
MAX_BOUNCES = 64


def ring_weights(r, dr: float) -> np.ndarray:
    """``w = 2 r/Δr``: the weight of a particle at radius ``r`` of new gas
    placed uniformly over the r–z plane (module docstring)."""
    return 2.0 * np.asarray(r, float) / dr


def fill_factor(dr: float) -> float:
    """The factor ``π Δr`` by which density and pressure are scaled for a fill
    uniform over the r–z plane at ``w = 2 r/Δr``
    (:func:`~partmesh.particle.dsmc.gas.particles_in_cells` counts ρ A/m
    particles over an area A; the ring of area A at radius r holds 2π r A ρ,
    i.e. ρ A/m particles of weight 2r/Δr times π Δr)."""
    return math.pi * dr


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def radial_flight(x, v, w, dt, R, outer):
    """The radial part of the free flight (module docstring) of particles
    ``x`` (n, 2: r, z) with velocities ``v`` (n, 3: v_r, v_z, v_θ) and
    weights ``w``, in place, inside the cylinder r ≤ ``R`` whose side is
    ``outer`` (REFLECT or OPEN). Returns ``(gone, delivered)``: the
    particles that left through an open side, and the momentum per unit
    mass handed to a reflecting side, Σ 2 w |v_n| over the bounces."""
    n = x.shape[0]
    gone = np.zeros(n, dtype=np.bool_)
    delivered = 0.0
    R2 = R * R
    for i in numba.prange(n):
        X, Y = x[i, 0], 0.0
        vx, vy = v[i, 0], v[i, 2]
        left = dt
        landed = False
        for _ in range(MAX_BOUNCES):
            Xe, Ye = X + vx * left, Y + vy * left
            if Xe * Xe + Ye * Ye <= R2:
                X, Y = Xe, Ye
                landed = True
                break
            if outer != REFLECT:
                gone[i] = True
                break
            # the crossing of the cylinder: |(X, Y) + t (vx, vy)|² = R², the root ahead
            a = vx * vx + vy * vy
            b = X * vx + Y * vy
            c = min(X * X + Y * Y - R2, 0.0)
            t = min(max((-b + math.sqrt(max(b * b - a * c, 0.0))) / a, 0.0), left)
            X, Y = X + vx * t, Y + vy * t
            norm = math.sqrt(X * X + Y * Y)
            nx, ny = X / norm, Y / norm
            vn = vx * nx + vy * ny
            delivered += 2.0 * abs(vn) * w[i]
            vx, vy = vx - 2.0 * vn * nx, vy - 2.0 * vn * ny
            left -= t
        if gone[i]:
            continue
        if not landed:  # still grazing after MAX_BOUNCES: put on the wall
            scale = R / math.sqrt(X * X + Y * Y)
            X, Y = X * scale, Y * scale
        r = math.sqrt(X * X + Y * Y)
        cos, sin = (X / r, Y / r) if r > 0.0 else (1.0, 0.0)
        x[i, 0] = r
        v[i, 0] = vx * cos + vy * sin
        v[i, 2] = vy * cos - vx * sin
    return gone, delivered


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def resampled_starts(w, start, target, due):
    """The cell starts of the particles :func:`resampled_redraw` makes of
    those in cell order (cell c holds ``start[c]:start[c+1]``, weights
    ``w``): every cell with ≥ 2 particles that is ``due`` (all where
    ``due`` has no rows) holds ``M = max(2, round(Σw/target[c]))``, the
    others as many as before."""
    ncell = start.size - 1
    counts = np.empty(ncell + 1, dtype=np.int64)
    counts[0] = 0
    for c in numba.prange(ncell):
        a, b = start[c], start[c + 1]
        if b - a < 2 or (due.size > 0 and not due[c]):
            counts[c + 1] = b - a
            continue
        total = 0.0
        for i in range(a, b):
            total += w[i]
        counts[c + 1] = max(2, int(round(total / target[c])))
    return np.cumsum(counts)


def resampled_redraw(x, v, e, w, start, target, zeta, seed, step, mass, momentum, energy, out=None,
                     slopes=NO_SLOPES, due=EVERY_CELL):
    """The equilibrium redraw of weighted particles in cell order (cell c
    holds ``start[c]:start[c+1]``) that also resamples every cell with ≥ 2
    particles to ``M = max(2, round(Σw/target[c]))`` particles of weight
    ``Σw/M`` (module docstring). Returns ``(x, v, e, w, start)`` of the new
    particles, still in cell order; fills per cell the sums it conserves,
    ``mass`` (Σw), ``momentum`` (Σ w v, (ncell, 3)) and ``energy``
    (Σ w(½|v|² + e), e counted if ``zeta`` > 0). Cell c draws from the
    stream ``(seed, step, c)``.

    ``out``: buffers ``(x, v, e, w)`` to write the new particles into, the
    returned arrays being their leading parts; replaced by new ones with
    room (:func:`~partmesh.particle.dsmc.cells.particle_buffers`) where they
    are too short, which an inflow's particles then fill without copying
    the rest.

    ``slopes`` (ncell, 2, 4): the draw is about the cell's linear velocity and temperature
    profile (:mod:`partmesh.particle.dsmc.profile`) at the new positions.

    ``due`` (ncell,): the cells redrawn (:mod:`partmesh.particle.dsmc.intervals`);
    the others keep their particles and weights as they are."""
    first = resampled_starts(w, start, target, due)
    m = int(first[-1])
    if out is None or min(a.shape[0] for a in out) < m:
        out = particle_buffers(m, x.shape[1], weighted=True)
    xs, vs, es, ws = (a[:m] for a in out)
    _resample_into(x, v, e, w, start, first, zeta, seed, step, mass, momentum, energy, xs, vs, es, ws, slopes, due)
    return xs, vs, es, ws, first


@numba.njit(parallel=PRANGE_ONLY, cache=True)
def _resample_into(x, v, e, w, start, first, zeta, seed, step, mass, momentum, energy, xs, vs, es, ws, slopes, due):
    """:func:`resampled_redraw` into ``xs, vs, es, ws``, cell c's new
    particles at ``first[c]:first[c+1]``."""
    ncell = start.size - 1
    dim = x.shape[1]
    for c in numba.prange(ncell):
        a, b, k0, k1 = start[c], start[c + 1], first[c], first[c + 1]
        S0, p0, p1, p2, total = weighted_sums(v, e, w, a, b, zeta)
        mass[c] = S0
        momentum[c, 0], momentum[c, 1], momentum[c, 2] = p0, p1, p2
        energy[c] = total
        if b - a < 2 or (due.size > 0 and not due[c]):
            for i in range(a, b):
                xs[k0 + i - a] = x[i]
                vs[k0 + i - a] = v[i]
                es[k0 + i - a] = e[i]
                ws[k0 + i - a] = w[i]
            continue
        M = k1 - k0
        W = S0 / M
        if zeta <= 0.0:  # (the draw sets no internal energy then, and a reused buffer holds old values)
            for k in range(k0, k1):
                es[k] = 0.0
        U0, U1, U2 = p0 / S0, p1 / S0, p2 / S0
        thermal = total - 0.5 * S0 * (U0 * U0 + U1 * U1 + U2 * U2)
        state = stream(seed, step, c)
        # systematic resampling of the positions: the k-th new particle sits where the running weight
        # passes (k + ξ) Σw/M, one ξ uniform in [0, 1) per cell (a fixed ξ would favour particles by
        # their place in the cell's order, which follows the cell they came from)
        state, xi = uniform(state)
        i, passed = a, w[a]
        for k in range(k0, k1):
            mark = (k - k0 + xi) * W
            while passed < mark and i < b - 1:
                i += 1
                passed += w[i]
            for d in range(dim):
                xs[k, d] = x[i, d]
            ws[k] = W
        # the equilibrium draw about the cell's velocity, as in equilibrate, at M particles of weight W
        state, m0, m1, m2, drawn = drawn_deviations(state, vs, es, k0, k1, zeta)
        if slopes.shape[0] > 0:
            redrawn_about_profile(xs, vs, es, k0, k1, U0, U1, U2, thermal, W, zeta, slopes, c)
        else:
            set_about(vs, es, k0, k1, U0, U1, U2, m0, m1, m2, max(thermal, 0.0) / (W * drawn), zeta)
