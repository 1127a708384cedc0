"""Particle → output-grid deposition (SPEC §2, "Deposition onto the output grid").

Particle solvers write their fields on the scene's output grid, like every
other method, so two results subtract directly. Two depositions live here:

* :func:`shepard` — SPH: kernel-normalised (Shepard) interpolation of particle
  fields at the output cell centres with the particles' own kernel and support
  radius; cells without fluid support are NaN.
* :func:`cell_average` with :func:`moments_to_primitive` — DSMC: per output
  cell, the sums of mass, momentum and energy carried by the simulated
  particles inside it (accumulated over a time window and/or ensembles by the
  caller), turned into density, velocity, pressure and specific internal
  energy by the ideal-gas relations.

Everything is vectorised (``scipy.spatial.cKDTree``, ``scipy.sparse``,
``np.bincount``): no Python loop runs over particles or cells. This module
imports numpy and scipy only.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import sparse
from scipy.spatial import cKDTree

from partmesh.compare.checks import InputError, in_range

__all__ = ["cell_average", "moments_to_primitive", "shepard"]

_GRID_RTOL = 1e-6  # a grid is uniform when every spacing matches the mean within this fraction


# --- input checks --------------------------------------------------------------


def _centres(name: str, c) -> np.ndarray:
    """A 1D array of finite, strictly increasing cell centres."""
    try:
        c = np.asarray(c, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a 1D array of finite cell centres.") from None
    if c.ndim != 1 or c.size < 1:
        raise InputError(f"{name} must be a 1D array of cell centres with at least one entry, got shape {c.shape}.")
    if not np.all(np.isfinite(c)):
        raise InputError(f"{name} must hold finite cell centres only.")
    if c.size > 1 and np.any(np.diff(c) <= 0):
        raise InputError(f"{name} must be strictly increasing.")
    return c


def _uniform(name: str, c: np.ndarray) -> float:
    """The spacing of uniform cell centres ``c`` (at least two)."""
    if c.size < 2:
        raise InputError(f"{name} must hold at least 2 cell centres, so that the cell width is defined; got {c.size}.")
    d = np.diff(c)
    h = (c[-1] - c[0]) / (c.size - 1)
    if np.max(np.abs(d - h)) > _GRID_RTOL * h:
        raise InputError(f"{name} must be uniformly spaced (spacing varies between {d.min():g} and {d.max():g}).")
    return h


def _points(points, dim: int) -> np.ndarray:
    """Particle positions as a finite (n, dim) array; (n,) is accepted in 1D."""
    try:
        pts = np.array(points, dtype=float)  # a copy: periodic wrapping edits it
    except (TypeError, ValueError):
        raise InputError("points must be a numeric (n, dim) array of particle positions.") from None
    if dim == 1 and pts.ndim == 1:
        pts = pts[:, None]
    if pts.ndim != 2 or pts.shape[1] != dim:
        need = "(n,) or (n, 1)" if dim == 1 else "(n, 2)"
        raise InputError(f"points must have shape {need} for a {dim}D grid, got shape {pts.shape}.")
    if not np.all(np.isfinite(pts)):
        raise InputError("points must hold finite particle positions only.")
    return pts


def _per_particle(name: str, a, n: int, *, positive: bool, allow_zero: bool = False) -> np.ndarray:
    """A per-particle array of shape (n,); a scalar is broadcast."""
    try:
        a = np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number or a numeric array of shape ({n},).") from None
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,):
        raise InputError(f"{name} must be a number or an array of shape ({n},) (one per particle), got shape {a.shape}.")
    if not np.all(np.isfinite(a)):
        raise InputError(f"{name} must hold finite values only.")
    if positive and a.size:
        bad = a < 0 if allow_zero else a <= 0
        if np.any(bad):
            bound = ">= 0" if allow_zero else "> 0"
            raise InputError(f"{name} must be {bound} for every particle, got a minimum of {a.min():g}.")
    return a


def _fields(name: str, values, n: int) -> tuple[np.ndarray, bool]:
    """Particle fields as (k, n); the flag says whether a single (n,) field was given."""
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a numeric array of shape ({n},) or (k, {n}).") from None
    single = v.ndim == 1
    if single:
        v = v[None, :]
    if v.ndim != 2 or v.shape[1] != n:
        raise InputError(f"{name} must have shape ({n},) or (k, {n}) (one column per particle), got shape {np.shape(values)}.")
    return v, single


def _periodicity(periodic, box, dim: int) -> tuple[np.ndarray, np.ndarray | None]:
    """Per-axis periodic flags and, where any axis is periodic, the (dim, 2) box."""
    if periodic is None:
        flags = np.zeros(dim, dtype=bool)
    else:
        flags = np.atleast_1d(np.asarray(periodic))
        if flags.shape != (dim,) or not all(isinstance(f, (bool, np.bool_)) for f in flags.tolist()):
            raise InputError(f"periodic must be None or {dim} booleans (one per axis), got {periodic!r}.")
        flags = flags.astype(bool)
    if not flags.any():
        return flags, None
    try:
        b = np.asarray(box, dtype=float)
    except (TypeError, ValueError):
        b = np.empty(0)
    if box is None or b.shape != (dim, 2) or not np.all(np.isfinite(b)) or np.any(b[:, 1] <= b[:, 0]):
        raise InputError(f"box must give a finite (lo, hi) with lo < hi for each of the {dim} axes when an axis is periodic, got {box!r}.")
    return flags, b


# --- SPH: Shepard interpolation --------------------------------------------------


def shepard(points, values, volumes, support, grid_x, grid_y=None, kernel=None,
            periodic=None, box=None, min_support=1e-3) -> np.ndarray:
    r"""Kernel-normalised (Shepard) SPH interpolation onto output cell centres.

    At every output cell centre x_g

    .. math::

        f(x_g) = \frac{\sum_j f_j V_j W(|x_g - x_j|, H_j)}{\sum_j V_j W(|x_g - x_j|, H_j)},
        \qquad V_j = m_j / \rho_j,

    with each particle's **own** compact support radius H_j (W = 0 for
    r >= H_j) and the caller's kernel W, so the grid sees the same smoothing
    as the solver. Dividing by the kernel sum (Shepard 1968; Randles &
    Libersky 1996, *Comput. Methods Appl. Mech. Engrg.* 139, 375; Price 2012,
    *J. Comput. Phys.* 231, 759, §3) makes the interpolant exact for a
    constant field everywhere it is defined, also next to a free surface or a
    wall, and exact for a linear field wherever the particles are arranged
    symmetrically about x_g (the interior of a uniform lattice).

    The denominator is the particles' local volume fraction (≈ 1 inside the
    fluid, → 0 outside it). Where it is below ``min_support`` the cell has no
    fluid support and is NaN (SPEC §2).

    Parameters
    ----------
    points : (n, dim) array (or (n,) in 1D)
        Positions of the (fluid) particles to deposit; pass fluid particles
        only, not wall, virtual or buffer particles.
    values : (n,) or (k, n) array
        Particle fields, one row per field. Non-finite values are not refused:
        they make every cell they reach NaN.
    volumes : (n,) array or number, > 0
        Particle volumes V_j = m_j / ρ_j (areas in 2D, lengths in 1D).
    support : (n,) array or number, > 0
        Compact support radius H_j of each particle's kernel.
    grid_x, grid_y : 1D arrays
        Output cell centres; ``grid_y=None`` for a 1D grid.
    kernel : callable ``kernel(r, H) -> W``
        Vectorised kernel: called with 1D arrays r (0 <= r < H) and H of one
        length, it returns W of that length.
    periodic : None or ``dim`` booleans
        Per-axis periodicity; periodic axes use the images x_j + m L of every
        particle (L = hi − lo of ``box``), all of them, so supports wider than
        the box are summed correctly.
    box : ((lo, hi),) * dim
        The periodic domain; needed when any axis is periodic. Positions on a
        periodic axis are wrapped into [lo, hi) first.
    min_support : float in [0, 1]
        Smallest kernel sum Σ V_j W (a fraction of full support) for which a
        cell is defined; cells with a kernel sum of zero are always NaN.

    Returns
    -------
    ndarray
        Shape ``([k,] [ny,] nx)`` in the schema layout (y, x): the ``k`` axis
        only when ``values`` is 2D, the ``ny`` axis only for a 2D grid.

    The result does not depend on the order of the particles, not even in the
    last bit: particles are put in a canonical order before summation.
    """
    if kernel is None or not callable(kernel):
        raise InputError(f"kernel must be a callable kernel(r, H) -> W, got {kernel!r}.")
    gx = _centres("grid_x", grid_x)
    gy = None if grid_y is None else _centres("grid_y", grid_y)
    dim = 1 if gy is None else 2
    pts = _points(points, dim)
    n = pts.shape[0]
    vals, single = _fields("values", values, n)
    vol = _per_particle("volumes", volumes, n, positive=True)
    H = _per_particle("support", support, n, positive=True)
    flags, b = _periodicity(periodic, box, dim)
    min_support = in_range("min_support", min_support, 0.0, 1.0)

    if gy is None:
        grid = gx[:, None]
        shape = (gx.size,)
    else:
        Y, X = np.meshgrid(gy, gx, indexing="ij")
        grid = np.column_stack([X.ravel(), Y.ravel()])
        shape = (gy.size, gx.size)
    k = vals.shape[0]
    ng = grid.shape[0]

    if n == 0:
        out = np.full((k,) + shape, np.nan)
        return out[0] if single else out

    # wrap positions on periodic axes into [lo, hi)
    if b is not None:
        for a in np.flatnonzero(flags):  # loop over axes, not particles
            lo, L = b[a, 0], b[a, 1] - b[a, 0]
            wrapped = lo + np.mod(pts[:, a] - lo, L)
            pts[:, a] = np.where(wrapped >= b[a, 1], lo, wrapped)  # mod can round up to L

    # canonical particle order, so the floating-point sums do not depend on it
    order = np.lexsort(tuple(vals[::-1]) + (vol, H) + tuple(pts.T[::-1]))
    pts, vals, vol, H = pts[order], vals[:, order], vol[order], H[order]

    Hmax = float(H.max())
    src = np.arange(n)
    if b is not None:
        gmin, gmax = grid.min(axis=0), grid.max(axis=0)
        for a in np.flatnonzero(flags):  # images along each periodic axis (loop over shifts)
            lo, hi = b[a]
            L = hi - lo
            m_lo = math.floor((gmin[a] - Hmax - hi) / L)
            m_hi = math.ceil((gmax[a] + Hmax - lo) / L)
            shifts = np.arange(m_lo, m_hi + 1) * L
            img = np.repeat(pts[None], shifts.size, axis=0)
            img[:, :, a] += shifts[:, None]
            img = img.reshape(-1, dim)
            img_src = np.tile(src, shifts.size)
            near = (img[:, a] > gmin[a] - Hmax) & (img[:, a] < gmax[a] + Hmax)
            pts, src = img[near], img_src[near]

    pairs = cKDTree(grid).sparse_distance_matrix(cKDTree(pts), Hmax, output_type="ndarray")
    g, j, r = pairs["i"], src[pairs["j"]], pairs["v"]
    inside = r < H[j]
    g, j, r = g[inside], j[inside], r[inside]

    if r.size:
        W = np.asarray(kernel(r, H[j]), dtype=float)
        if W.shape != r.shape:
            raise InputError(f"kernel must return one value per distance (shape {r.shape}), got shape {W.shape}.")
        if not np.all(np.isfinite(W)):
            raise InputError("kernel must return finite values for 0 <= r < H.")
    else:
        W = np.zeros(0)
    A = sparse.csr_matrix((vol[j] * W, (g, j)), shape=(ng, n))
    den = np.asarray(A.sum(axis=1)).ravel()
    num = np.asarray(A @ vals.T).T  # (k, ng)
    ok = (den > 0) & (den >= min_support)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(ok, num / np.where(ok, den, 1.0), np.nan)
    out = out.reshape((k,) + shape)
    return out[0] if single else out


# --- DSMC: cell sums and moments --------------------------------------------------


def _bins(name: str, c: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Cell index of every coordinate x on uniform centres c (edges halfway between
    centres, cells half-open [left, right)); -1 outside the grid."""
    h = _uniform(name, c)
    edges = np.concatenate([[c[0] - 0.5 * h], 0.5 * (c[:-1] + c[1:]), [c[-1] + 0.5 * h]])
    i = np.searchsorted(edges, x, side="right") - 1
    return np.where((i >= 0) & (i < c.size), i, -1)


def cell_average(points, weights, quantities, grid_x, grid_y=None) -> tuple[np.ndarray, np.ndarray]:
    r"""Per-cell sums of weighted particle quantities on the output grid (DSMC).

    For every output cell c

    .. math::

        S_{q,c} = \sum_{j \in c} w_j\, q_j, \qquad N_c = \#\{j \in c\},

    where a particle belongs to the cell whose half-open box
    [left edge, right edge) (× [bottom, top)) holds it, the edges lying halfway
    between the uniform cell centres and half a spacing beyond the outermost
    ones. Particles outside the grid are dropped, so Σ_c S_c is the sum over
    the particles inside the grid exactly (up to round-off).

    For the DSMC moments (Bird 1994, *Molecular Gas Dynamics and the Direct
    Simulation of Gas Flows*, §1.4, with F_N molecules of mass m per simulated
    particle) pass ``weights = F_N m`` and
    ``quantities = [1, c_x, c_y, ½|c|² + ε_int/m]``: the sums are the cell's
    mass, momentum and total energy (translational + internal), ready for
    :func:`moments_to_primitive`. To average over a time window or an
    ensemble, add the sums of the samples and pass the cell volume times the
    number of samples to :func:`moments_to_primitive`.

    Parameters
    ----------
    points : (n, dim) array (or (n,) in 1D)
        Particle positions; dim = 2 when ``grid_y`` is given, else 1.
    weights : (n,) array or number, >= 0
        Weight of each particle (e.g. F_N m).
    quantities : (n,) or (k, n) array
        Per-particle quantities q_j, one row per quantity.
    grid_x, grid_y : 1D arrays
        Uniformly spaced output cell centres, at least two per axis;
        ``grid_y=None`` for a 1D grid.

    Returns
    -------
    sums : ndarray, shape ``([k,] [ny,] nx)``
        Weighted sums (the ``k`` axis only when ``quantities`` is 2D).
    counts : int ndarray, shape ``([ny,] nx)``
        Number of particles in each cell.
    """
    gx = _centres("grid_x", grid_x)
    gy = None if grid_y is None else _centres("grid_y", grid_y)
    dim = 1 if gy is None else 2
    pts = _points(points, dim)
    n = pts.shape[0]
    w = _per_particle("weights", weights, n, positive=True, allow_zero=True)
    q, single = _fields("quantities", quantities, n)
    if not np.all(np.isfinite(q)):
        raise InputError("quantities must hold finite values only.")

    ix = _bins("grid_x", gx, pts[:, 0])
    if gy is None:
        shape = (gx.size,)
        flat, keep = ix, ix >= 0
    else:
        iy = _bins("grid_y", gy, pts[:, 1])
        shape = (gy.size, gx.size)
        flat, keep = iy * gx.size + ix, (ix >= 0) & (iy >= 0)
    flat = flat[keep]
    size = int(np.prod(shape))
    counts = np.bincount(flat, minlength=size).reshape(shape)
    A = sparse.csr_matrix((w[keep], (flat, np.flatnonzero(keep))), shape=(size, n))
    sums = np.asarray(A @ q.T).T.reshape((q.shape[0],) + shape)
    return (sums[0] if single else sums), counts


def moments_to_primitive(mass, momentum, energy, volume, gamma):
    r"""Density, velocity, pressure and specific internal energy from cell moments.

    With the cell's mass M, momentum P and **total** energy E (translational
    kinetic energy of the molecules, bulk flow included, plus their internal
    — rotational — energy; J), and the cell volume V, the ideal-gas relations
    (Bird 1994, §1.4; e = c_v T, p = ρ R T, c_v = R/(γ − 1)) give

    .. math::

        \rho = \frac{M}{V}, \quad \mathbf u = \frac{\mathbf P}{M}, \quad
        e = \frac{E - |\mathbf P|^2 / (2M)}{M}, \quad
        p = (\gamma - 1)\, \rho\, e = (\gamma - 1) \frac{E - |\mathbf P|^2/(2M)}{V}.

    For a diatomic gas with ζ = 2 internal degrees of freedom, the thermal part
    E − |P|²/2M = (3 + ζ)/2 · N k T, so p = N k T / V with γ = (5 + ζ)/(3 + ζ).

    Parameters
    ----------
    mass : array, >= 0
        Cell mass M (kg), any shape S.
    momentum : array of shape S (1D flow) or ``(d, *S)``, d = 1, 2 or 3
        Cell momentum components (kg m s-1); components not given have zero
        mean (their fluctuations are part of E).
    energy : array of shape S, >= 0
        Cell total energy E (J), translational + internal.
    volume : number or array broadcastable to S, > 0
        Cell volume V (m³; in 2D the cell area times the depth the particle
        weights stand for). For sums over n samples, pass n × the volume.
    gamma : number > 1
        Ratio of specific heats.

    Returns
    -------
    tuple ``(rho, u, [v, [w,]] p, e)``
        One velocity per momentum component. Empty cells (M = 0) have
        ρ = 0 and p = 0 (no particles, no energy) and NaN velocity and e.
    """
    gamma = in_range("gamma", gamma, 1.0, math.inf, lo_open=True, hi_open=True)
    try:
        M = np.asarray(mass, dtype=float)
        P = np.asarray(momentum, dtype=float)
        E = np.asarray(energy, dtype=float)
        V = np.asarray(volume, dtype=float)
    except (TypeError, ValueError):
        raise InputError("mass, momentum, energy and volume must be numeric arrays.") from None
    if not np.all(np.isfinite(M)) or np.any(M < 0):
        raise InputError("mass must hold finite values >= 0.")
    if P.shape == M.shape:
        P = P[None]
    if P.ndim != M.ndim + 1 or P.shape[1:] != M.shape or not 1 <= P.shape[0] <= 3:
        raise InputError(f"momentum must have the shape of mass {M.shape} or (d, *{M.shape}) with d = 1, 2 or 3, got {np.shape(momentum)}.")
    if not np.all(np.isfinite(P)):
        raise InputError("momentum must hold finite values only.")
    if E.shape != M.shape:
        raise InputError(f"energy must have the shape of mass {M.shape}, got {E.shape}.")
    if not np.all(np.isfinite(E)) or np.any(E < 0):
        raise InputError("energy must hold finite values >= 0 (total energy per cell, J).")
    if not np.all(np.isfinite(V)) or np.any(V <= 0):
        raise InputError("volume must be finite and > 0.")
    try:
        V = np.broadcast_to(V, M.shape)
    except ValueError:
        raise InputError(f"volume must be a number or broadcastable to the shape of mass {M.shape}, got {np.shape(volume)}.") from None

    full = M > 0
    Msafe = np.where(full, M, 1.0)
    vel = np.where(full, P / Msafe, np.nan)
    kinetic = np.where(full, 0.5 * np.sum(P * P, axis=0) / Msafe, 0.0)
    thermal = E - kinetic
    rho = M / V
    p = (gamma - 1.0) * thermal / V
    e = np.where(full, thermal / Msafe, np.nan)
    return (rho, *vel, p, e)
