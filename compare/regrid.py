"""Moving cell-centred fields between uniform meshes (SPEC §2, "Deposition").

A solver may march on a grid that differs from the scene's output grid; its
fields are brought onto the output grid here, and the caller records the
returned ``how`` in the result's attributes:

* ``"identity"`` — the grids are the same: the values are copied;
* ``"conservative average"`` — the source grid is an integer factor k finer
  (per axis) than the output grid and every output cell is exactly a block of
  k (× k) source cells: the output value is the block's cell average, so the
  integral of the field over the output cells equals the integral over the
  source cells it covers (the finite-volume meaning of a cell value, LeVeque
  2002, *Finite Volume Methods for Hyperbolic Problems*, §4.1);
* ``"linear interpolation"`` — any other pair of grids: (bi)linear
  interpolation between source cell centres, with the source edge value held
  beyond the outermost source centres (clamping).

Both averaging and interpolation are NaN-aware, so cells inside solids (NaN)
do not poison their fluid neighbours; see :func:`to_output_grid`.
"""

from __future__ import annotations

import itertools

import numpy as np

__all__ = ["to_output_grid", "HOW"]

#: the three ways :func:`to_output_grid` can move a field, as written to attrs.
HOW = ("identity", "conservative average", "linear interpolation")

_SAME_RTOL = 1e-9  # two centres are "the same" within this fraction of the spacing
_GRID_RTOL = 1e-6  # uniform spacing, integer ratio and edge alignment within this fraction


def _axis(name: str, c, n: int | None = None) -> tuple[np.ndarray, float]:
    """Validate a cell-centre coordinate: 1D, finite, strictly increasing, uniform."""
    c = np.asarray(c, dtype=float)
    if c.ndim != 1 or c.size < 1:
        raise ValueError(f"{name} must be a 1D array of cell centres with at least one entry, got shape {c.shape}.")
    if not np.all(np.isfinite(c)):
        raise ValueError(f"{name} must hold finite cell centres only.")
    if n is not None and c.size != n:
        raise ValueError(f"{name} has {c.size} entries but values have {n} cells along that axis; they must match.")
    if c.size == 1:
        return c, np.nan
    d = np.diff(c)
    if np.any(d <= 0):
        raise ValueError(f"{name} must be strictly increasing.")
    h = (c[-1] - c[0]) / (c.size - 1)
    if np.max(np.abs(d - h)) > _GRID_RTOL * h:
        raise ValueError(f"{name} must be uniformly spaced (spacing varies between {d.min():g} and {d.max():g}).")
    return c, h


def _same(src: np.ndarray, dst: np.ndarray, h: float) -> bool:
    if src.size != dst.size:
        return False
    scale = h if np.isfinite(h) else max(1.0, abs(src[0]))
    return bool(np.all(np.abs(src - dst) <= _SAME_RTOL * scale))


def _blocks(src: np.ndarray, hs: float, dst: np.ndarray, hd: float) -> tuple[int, int] | None:
    """(offset m, factor k) if every dst cell is exactly source cells m + k j ... m + k j + k - 1."""
    if src.size < 2 or dst.size < 1:
        return None
    if dst.size == 1:
        return None  # a single output cell has no spacing to compare; interpolate instead
    kf = hd / hs
    k = int(round(kf))
    if k < 1 or abs(kf - k) > _GRID_RTOL * k:
        return None
    edge_src = src[0] - 0.5 * hs
    edge_dst = dst[0] - 0.5 * hd
    mf = (edge_dst - edge_src) / hs
    m = int(round(mf))
    if m < 0 or abs(mf - m) > _GRID_RTOL * k:
        return None
    if m + k * dst.size > src.size:
        return None
    return m, k


def _block_mean(v: np.ndarray, blocks: list[tuple[int, int, int]]) -> np.ndarray:
    """NaN-aware mean over aligned blocks of the trailing axes; blocks = [(m, k, n_dst)] per axis."""
    lead = v.shape[: v.ndim - len(blocks)]
    sl = tuple(slice(m, m + k * n) for m, k, n in blocks)
    v = v[(Ellipsis,) + sl]
    shape = lead
    for _, k, n in blocks:
        shape = shape + (n, k)
    v = v.reshape(shape)
    red = tuple(len(lead) + 2 * i + 1 for i in range(len(blocks)))
    ok = np.isfinite(v)
    count = ok.sum(axis=red)
    total = np.where(ok, v, 0.0).sum(axis=red)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / np.maximum(count, 1), np.nan)


def linear_weights(src: np.ndarray, hs: float, dst: np.ndarray, periodic: bool = False):
    """Indices i0, i1 and weight w of the points ``dst`` between the uniform
    centres ``src`` (spacing ``hs``), q(dst) = (1 − w) q[i0] + w q[i1]:
    wrapped around a periodic axis, else clamped at the ends."""
    n = src.size
    if periodic:
        f = (dst - src[0]) / hs
        i0 = np.floor(f).astype(int)
        return i0 % n, (i0 + 1) % n, f - i0
    if n == 1:
        z = np.zeros(dst.size, dtype=int)
        return z, z, np.zeros(dst.size)
    f = np.clip((dst - src[0]) / hs, 0.0, n - 1.0)
    i0 = np.minimum(np.floor(f).astype(int), n - 2)
    w = f - i0
    return i0, i0 + 1, w


def _interp(v: np.ndarray, axes: list[tuple[np.ndarray, np.ndarray, np.ndarray]]) -> np.ndarray:
    """NaN-aware (bi-, tri-)linear interpolation on the trailing axes: the
    tensor product of the axes' weights over the 2^d corners."""
    d = len(axes)
    num = 0.0
    den = 0.0
    for corner in itertools.product((0, 1), repeat=d):  # 2^d corner terms, not a loop over cells
        index, weight = [], 1.0
        for a, (bit, (i0, i1, w)) in enumerate(zip(corner, axes)):
            shape = [1] * d
            shape[a] = -1
            index.append((i1 if bit else i0).reshape(shape))
            weight = weight * (w if bit else 1.0 - w).reshape(shape)
        val = v[(Ellipsis, *index)]
        ok = np.isfinite(val) & (weight > 0)
        num = num + np.where(ok, val * weight, 0.0)
        den = den + np.where(ok, weight, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / np.where(den > 0, den, 1.0), np.nan)


def to_output_grid(values, src_x, dst_x, src_y=None, dst_y=None, src_z=None, dst_z=None,
                   periodic=(False, False, False)) -> tuple[np.ndarray, str]:
    """Move a cell-centred field from a uniform source grid onto a uniform output grid.

    Parameters
    ----------
    values : array of shape ``([n,] [[nz,] ny,] nx)``
        The field on the source grid: ``(nx,)`` or ``(n, nx)`` in 1D,
        ``(ny, nx)`` or ``(n, ny, nx)`` in 2D, ``(nz, ny, nx)`` or
        ``(n, nz, ny, nx)`` in 3D; a leading axis (e.g. time) is
        carried through unchanged. NaN marks cells without a value (solids).
    src_x, dst_x : 1D arrays
        Cell centres of the source and output grids along x, strictly
        increasing and uniformly spaced.
    src_y, dst_y, src_z, dst_z : 1D arrays, optional
        The same along y for 2D and 3D fields and along z for 3D fields
        (give both of a pair or neither; z only with y).
    periodic : bools, one per axis (x, y, z; missing ones False)
        Whether the domain wraps around along each axis: linear interpolation
        then takes the neighbours across the periodic side instead of
        clamping.

    Returns
    -------
    (values_on_dst, how) with ``how`` one of :data:`HOW`:

    * ``"identity"``: same grids, the values are copied.
    * ``"conservative average"``: along every axis the output spacing is an
      integer multiple k ≥ 1 of the source spacing and each output cell's
      edges coincide with source cell edges (output cell j covers source
      cells m + k j … m + k j + k − 1). Then

          q_J = Σ_{i ∈ J} q_i ΔV_i / Σ_{i ∈ J} ΔV_i = mean of the k (× k) block,

      so Σ_J q_J ΔV_J = Σ_i q_i ΔV_i over the covered cells (exact
      conservation; LeVeque 2002, *Finite Volume Methods for Hyperbolic
      Problems*, §4.1). NaN cells are left out of a block's mean; an all-NaN
      block gives NaN.
    * ``"linear interpolation"``: otherwise,
      q(x) = (1 − w) q_i + w q_{i+1}, w = (x − x_i)/Δx (the tensor product of
      that in 2D), with output centres beyond the outermost source centres
      given the edge value (clamping) or, on a periodic axis, interpolated
      across the periodic side. NaN corner values are dropped and the
      remaining weights renormalised; NaN if every corner with a non-zero
      weight is NaN.

    Raises
    ------
    ValueError
        With one sentence naming the offending parameter: non-uniform or
        non-increasing coordinates, a coordinate whose length differs from
        the matching axis of ``values``, or one of a pair given alone.
    """
    v = np.asarray(values, dtype=float)
    for axis, src, dst in (("y", src_y, dst_y), ("z", src_z, dst_z)):
        if (src is None) != (dst is None):
            raise ValueError(f"src_{axis} and dst_{axis} must be given together or both left out.")
    if src_z is not None and src_y is None:
        raise ValueError("src_z and dst_z need src_y and dst_y (a 3D field).")
    given = [(n, s, d) for n, s, d in (("x", src_x, dst_x), ("y", src_y, dst_y), ("z", src_z, dst_z)) if s is not None]
    need = len(given)
    if v.ndim not in (need, need + 1):
        layout = ("nx", "ny, nx", "nz, ny, nx")[need - 1]
        raise ValueError(f"values must have shape ([n,] {layout}) ({need} or {need + 1} dimensions), "
                         f"got {v.ndim} dimensions.")
    # (the array's axes run z, y, x: the last axis is x)
    pairs = [(*_axis(f"src_{n}", s, v.shape[-1 - a]), *_axis(f"dst_{n}", d)) for a, (n, s, d) in enumerate(given)][::-1]

    if all(_same(s, d, hs) for s, hs, d, _ in pairs):
        return v.copy(), "identity"

    blocks = [_blocks(s, hs, d, hd) for s, hs, d, hd in pairs]
    if all(b is not None for b in blocks):
        spec = [(m, k, d.size) for (m, k), (_, _, d, _) in zip(blocks, pairs)]
        return _block_mean(v, spec), "conservative average"

    wraps = [bool(periodic[a]) if a < len(periodic) else False for a in range(need)][::-1]
    axes = [linear_weights(s, hs, d, wrap) for (s, hs, d, _), wrap in zip(pairs, wraps)]
    return _interp(v, axes), "linear interpolation"
