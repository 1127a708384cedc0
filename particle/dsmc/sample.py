"""Moments of DSMC particles on a uniform grid (SPEC §3.3, §2).

Per cell the sums S0 = N, S1 = Σ v (three components) and
S2 = Σ (½|v|² + e) of the particles in it, accumulated over the samples of
a time window (and over ensembles), give the state

    ρ = m S0/(K V),   U = S1/S0,   e_th = S2/S0 − ½ Σ_{a<d} U_a²,   p = (γ − 1) ρ e_th,

K the number of samples, m the particle mass, V the cell volume (the
cumulative-sampling estimate: averages of sums, not of per-sample states).
Weighted particles (r–z, :mod:`~partmesh.particle.dsmc.axisymmetric`) count
by their weights: S0 = Σ w, S1 = Σ w v, S2 = Σ w (½|v|² + e), and V is the
ring cell's volume 2π r_c Δr Δz.
The bulk velocity along the axes the problem does not resolve (z, and y in
1D) is only scatter about zero, so its energy counts as thermal: the
schema's ρ(e + ½|u|²) summed over the cells is the particles' energy.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from partmesh.particle.dsmc.cells import cell_index


class CellState(NamedTuple):
    """The state of the cells from their moments: density, the three
    velocity components (those along axes the scene does not resolve are
    scatter about zero), pressure and specific internal energy."""

    rho: np.ndarray
    u: np.ndarray
    v: np.ndarray
    w: np.ndarray
    p: np.ndarray
    e: np.ndarray


class CellSums:
    """Running sums S0, S1, S2 per cell of a uniform grid over K samples;
    ``fraction`` (grid-shaped, (ny, nx) in 2D) is the part of each cell's
    volume open to the gas (1 without obstacles; 0: a solid cell, NaN state);
    ``radial``: the cells are rings about the axis x = 0 (2D)."""

    def __init__(self, lo, spacing, shape, fraction=None, radial=False):
        self.lo, self.spacing, self.shape = np.asarray(lo, float), np.asarray(spacing, float), tuple(shape)
        self.ncell = int(np.prod(self.shape))
        self.shape_array = np.array(self.shape, dtype=np.int64)
        volume = float(np.prod(self.spacing))
        self.volume = volume * (np.ones(self.ncell) if fraction is None else np.asarray(fraction, float).reshape(-1))
        if radial:
            r = self.lo[0] + (np.arange(self.shape[0]) + 0.5) * self.spacing[0]
            self.volume *= np.tile(2.0 * np.pi * r, self.ncell // self.shape[0])
        self.reset()

    def reset(self):
        self.samples = 0
        self.count = np.zeros(self.ncell)  # the particles sampled (unweighted)
        self.s0 = np.zeros(self.ncell)
        self.s1 = np.zeros((self.ncell, 3))
        self.s2 = np.zeros(self.ncell)

    def add(self, x, v, e, w=None):
        """Add one sample of the particles ``(x, v, e)``, of weights ``w`` if given."""
        cell = cell_index(x, self.lo, self.spacing, self.shape_array)
        self.count += np.bincount(cell, minlength=self.ncell)
        self.s0 += np.bincount(cell, w, minlength=self.ncell)
        for a in range(3):
            self.s1[:, a] += np.bincount(cell, v[:, a] if w is None else w * v[:, a], minlength=self.ncell)
        heat = 0.5 * np.einsum("ij,ij->i", v, v) + e
        self.s2 += np.bincount(cell, heat if w is None else w * heat, minlength=self.ncell)
        self.samples += 1

    def same_grid(self, other: "CellSums") -> bool:
        """Whether ``other`` sums over the same cells."""
        return (self.shape == other.shape and np.array_equal(self.lo, other.lo)
                and np.array_equal(self.spacing, other.spacing))

    def add_sums(self, other: "CellSums"):
        """Add the samples ``other`` holds, on the same grid."""
        self.count += other.count
        self.s0 += other.s0
        self.s1 += other.s1
        self.s2 += other.s2
        self.samples += other.samples

    def state(self, mass, gamma) -> "CellState":
        """The :class:`CellState` per cell (NaN velocity and pressure where no
        particle was sampled), each of the grid's shape ((ny, nx) in 2D, (nz, ny, nx) in 3D)."""
        rho, U, p, e = moment_state(self.s0, self.s1, self.s2, self.volume, self.samples, mass, gamma,
                                    len(self.shape))
        grid = tuple(reversed(self.shape))
        return CellState(*(q.reshape(grid) for q in (rho, U[:, 0], U[:, 1], U[:, 2], p, e)))


def moment_state(s0, s1, s2, volume, samples, mass, gamma, resolved):
    """``(rho, U, p, e)`` of moment sums (module docstring) per entry:
    ``s0`` (n,), ``s1`` (n, 3), ``s2`` (n,) accumulated over ``samples``
    samples in open volumes ``volume`` (n,); the first ``resolved`` velocity
    components are the flow's, the others' energy counts as thermal. NaN
    density where the volume is 0, NaN velocity and pressure where no
    particle was sampled."""
    with np.errstate(invalid="ignore", divide="ignore"):
        rho = np.where(volume > 0.0, mass * s0 / (max(samples, 1) * volume), np.nan)
        U = s1 / s0[:, None]
        flow = U[:, :resolved]
        e = s2 / s0 - 0.5 * np.einsum("ij,ij->i", flow, flow)
    return rho, U, (gamma - 1.0) * rho * e, e


def unbiased_pressure(p, count, resolved, zeta):
    """The pressure of one sample of ``count`` particles per cell, freed of
    the bias of :func:`moment_state`'s thermal energy.

    The flow velocity U of a cell is the mean of its N particles, so ½|U|²
    takes in the variance θ/N of that mean in each of the ``resolved``
    components d: for particles in equilibrium at temperature θ with
    ``zeta`` internal degrees ζ, E[e_th] = ½(3 + ζ) θ (1 − d/((3 + ζ) N)),
    and

        p̂ = p / (1 − d/((3 + ζ) N))

    is unbiased (−1.3 % without it at 30 particles of air in 2D). In r–z
    N counts particles whose weights differ by the ratio of neighbouring
    radii, so their effective number (Σw)²/Σw² is N to about a per cent
    from the fifth ring out (less next to the axis, where the correction
    falls short). Exact for one sample; for sums over several steps the
    variance of U is not θ/(KN) (the redraw keeps a cell's momentum from
    step to step), so the output frames keep the plain estimator, whose
    cell energies sum to the particles'. NaN where no particle was
    sampled."""
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, p / (1.0 - resolved / ((3.0 + zeta) * count)), np.nan)


def probe_cells(cells: CellSums, points, shells):
    """Per probe, the cells it reads and their weights.

    A probe at ``points[k]`` reads the cell holding it; a shell probe
    (``shells[k]``, :class:`~partmesh.cases.parts.Probe`) also every cell
    whose centre lies within half a cell spacing of the sphere (r–z) or
    circle (planar) through it about the origin, each weighted by its open
    volume V_c, so that its reading Σ V_c p_c / Σ V_c (:func:`probe_pressures`)
    is the shell's mean pressure, its scatter falling as one over the root of
    the cells on it."""
    own = cell_index(np.asarray(points, float), cells.lo, cells.spacing, cells.shape_array)
    index = np.indices(tuple(reversed(cells.shape))).reshape(len(cells.shape), -1)[::-1]  # (dim, ncell), x fastest
    centres = cells.lo[:, None] + (index + 0.5) * cells.spacing[:, None]
    distance = np.sqrt(np.sum(centres * centres, axis=0))
    half = 0.5 * float(np.max(cells.spacing))
    read = []
    for point, cell, shell in zip(np.asarray(points, float), own, shells):
        members = np.array([cell])
        if shell:
            radius = float(np.sqrt(np.sum(point * point)))
            members = np.union1d(members, np.nonzero(np.abs(distance - radius) < half)[0])
        read.append((members, cells.volume[members] if shell else np.ones(1)))
    return read


def probe_pressures(p, read):
    """The reading of every probe from the cell pressures ``p`` (flat, x
    fastest) and the cells and weights of :func:`probe_cells`: Σ w_c p_c / Σ w_c
    over the cells that hold particles (NaN where none does)."""
    out = np.empty(len(read))
    for k, (members, weights) in enumerate(read):
        values = p[members]
        held = np.isfinite(values) & (weights > 0)
        out[k] = np.sum(weights[held] * values[held]) / np.sum(weights[held]) if held.any() else np.nan
    return out
