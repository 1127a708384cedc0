"""The state of a block-structured hierarchy and the operations between its
levels (Berger & Colella 1989, J. Comput. Phys. 82, 64), as pure functions
of arrays on the device.

Every level is stored whole, block-major (:mod:`partmesh.gridref.amr.layout`),
and only its active blocks are advanced: a static-capacity list of their
ids, padded with the id one past the last block, which gathers clamp and
scatters drop. Around a level's active blocks lies its *halo*, the blocks
one block away: before each step of the level they are filled from the
coarser level, interpolated in time, so the active blocks read their
ghost cells from storage whatever lies next to them.

After a coarser level's step its finer level takes two steps of half the
size; then the fine blocks' means replace the coarse cells they cover
(restriction), and every coarse cell next to the fine region has its
flux through the coarse–fine face replaced by the fine level's flux summed
over its two steps (refluxing), so the hierarchy conserves mass, momentum
and energy to round-off. In a geometry of revolution (x the radius) every
mean is weighted by the cells' volumes and every flux by its face's area
(:mod:`partmesh.gridref.revolution`), so the totals conserved are those of
the revolved body. A regrid (:func:`regridded`) sets every level's
blocks from the error estimate of the level below, with a buffer of blocks,
proper nesting, and the new blocks filled by conservative prolongation.
"""

from __future__ import annotations

from typing import Callable, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.gridref.amr import blockmaps
from partmesh.gridref.amr.layout import Layout, coords_of, flat_id
from partmesh.gridref.amr.sensor import child_maxima, lohner, variation
from partmesh.gridref.amr.tiling import over_chunks
from partmesh.gridref.amr.transfer import prolonged, restricted, volume_shift
from partmesh.gridref.amr.windows import block_origins, gathered, sources
from partmesh.gridref.revolution import RadialTable


class Hierarchy(NamedTuple):
    """The state of every level.

    ``U[l]``: the conservative variables of level ``l`` (a tuple of
    block-major arrays); ``old[l]`` (levels with a finer one): the state of
    its active blocks when its step under way began; ``flux[l][d]`` (levels
    with a finer one): Δt times the flux through every face normal to axis
    ``d`` of its active blocks in its last step; ``register[l][d]``
    (levels with a coarser one): the sum over the current pair of steps of
    Δt times the flux through each active block's two boundary faces normal
    to ``d``; ``active[l]``, ``halo[l]``: ``(ids, count)``; ``maps[l]``:
    the active blocks as a boolean map; ``floors``: cells the vacuum floors
    changed and the mass and energy they added; ``updates``: cell updates
    made; ``need``: the list lengths the last regrid asked for, per level
    (active, halo); ``dt_limit``: the
    largest step of level 0 the next may take, however stable
    (:data:`GROWTH` times the last); ``peak``: the most active blocks each
    level has held, and (last) the most all levels have held at once;
    ``steps``: the steps of level 0 taken (the regrids fall on multiples
    of their interval)."""

    U: tuple
    old: tuple
    flux: tuple
    register: tuple
    active: tuple
    halo: tuple
    maps: tuple
    floors: jnp.ndarray
    updates: jnp.ndarray
    need: jnp.ndarray
    dt_limit: jnp.ndarray
    peak: jnp.ndarray
    steps: jnp.ndarray


#: the fields of a :class:`Hierarchy` that hold one entry per level
PER_LEVEL = ("U", "old", "flux", "register", "active", "halo", "maps")


def from_level(H: Hierarchy, level: int) -> Hierarchy:
    """``H`` with the entries of the levels coarser than ``level`` None: what
    the steps of levels ``level`` and finer change (a loop over them carries
    it, and reads the coarser levels as constants, which it need not copy)."""
    return H._replace(**{f: (None,) * level + getattr(H, f)[level:] for f in PER_LEVEL})


def joined(coarse: Hierarchy, fine: Hierarchy, level: int) -> Hierarchy:
    """The hierarchy of ``coarse``'s levels below ``level`` and ``fine``'s
    from ``level`` on (:func:`from_level`), with ``fine``'s other fields."""
    return fine._replace(**{f: getattr(coarse, f)[:level] + getattr(fine, f)[level:] for f in PER_LEVEL})


#: how much a step of level 0 may exceed the one before (AMReX's ``change_max``): a finer level takes
#: 2^l steps of the size set at the start of a step of level 0, so a wave that speeds up inside it (a
#: Riemann problem's first steps) must not find the steps far beyond its own stable one
GROWTH = 1.1


#: the fine cells next to a block's side that a neighbour's window reads (its two ghost layers): the rim of a
#: halo block that :meth:`Levels.rims_filled` prolongs
RIM = 2


def with_level(levels: tuple, level: int, value) -> tuple:
    """The tuple over levels ``levels`` with entry ``level`` replaced by ``value``."""
    return levels[:level] + (value,) + levels[level + 1:]


def _pow2(n: int) -> int:
    return 1 << max(int(np.ceil(np.log2(max(n, 1)))), 0)


def capacity_for(count: int, most: int) -> int:
    """The capacity of a block list for ``count`` of a level's ``most``
    blocks: the next power of two at least a quarter above it (the list
    grows rarely; the blocks beyond ``count`` cost nothing, their chunks are
    not advanced), at most ``most``."""
    return min(_pow2(int(np.ceil(1.25 * count)) + 1), most)


class Levels:
    """The operations of one layout's hierarchy (``n_vars`` conserved
    variables): block gathers and scatters, transfers between levels,
    refluxing and regridding. ``admissible(U) -> bool array``: the states a
    prolongation may make (elsewhere it copies the parent);
    ``sensed(U) -> tuple of arrays``: the variables the error estimator
    reads; ``refine``, ``derefine``: the thresholds of Löhner's estimate (a
    level-``l`` cell above ``refine`` asks for level ``l + 1``; one above
    ``derefine`` keeps it) and ``gradient`` that of the relative variation
    (kept above ``gradient · derefine / refine``)
    (:mod:`partmesh.gridref.amr.sensor`); ``buffer``: blocks added around
    the flagged ones; ``radial``: the power k of r in the face areas of a
    geometry of revolution (0: planar); ``open_fraction``: the finest
    level's open volume fraction κ around bodies (the level's block-major
    storage; None: no bodies), from which every coarser level's is the
    mean, and the restriction weighs every child by it."""

    def __init__(self, layout: Layout, n_vars: int, admissible: Callable, sensed: Callable, refine: float,
                 derefine: float, gradient: float, buffer: int, radial: int = 0, open_fraction=None):
        self.layout, self.n_vars = layout, n_vars
        self.admissible, self.sensed = admissible, sensed
        self.refine, self.derefine, self.gradient, self.buffer = refine, derefine, gradient, buffer
        self.radial = radial
        #: per level, its radial geometry with two ghost cells beyond either end (None: planar)
        self.tables = [RadialTable(layout.cells(level)[0], layout.spacing(level)[0], radial, 2,
                                   layout.kinds[1] == "reflect") if radial else None
                       for level in range(layout.levels)]
        #: per level, the open volume fraction of every cell (None: no bodies)
        self.open_fractions = None if open_fraction is None else _coarsened(open_fraction, layout)

    def radii(self, level: int, ids, first: int = 0, n: int | None = None):
        """The global radial (x) indices of the cells ``first … first + n − 1``
        along x of every block ``ids`` of ``level``: (m, n); ``n`` a block's
        cells if None."""
        B = self.layout.block
        x = coords_of(ids, self.layout.blocks(level), jnp)[0] * B + first
        return x[:, None] + jnp.arange(B if n is None else n)[None, :]

    # --- storage -----------------------------------------------------------------------------------------
    def empty(self, level: int):
        """A level's storage, zero."""
        return tuple(jnp.zeros((self.layout.n_blocks(level), *self.layout.block_shape)) for _ in range(self.n_vars))

    def blocks_of(self, U, ids):
        """The blocks ``ids`` of a level's storage ``U`` (clamped ids)."""
        return tuple(a[ids] for a in U)

    @staticmethod
    def with_blocks(U, ids, values):
        """``U`` with the blocks ``ids`` set to ``values`` (ids past the end dropped)."""
        return tuple(a.at[ids].set(v, mode="drop") for a, v in zip(U, values))

    def windows(self, U, level: int, ids, ghosts: int, imposed=None):
        """Every block ``ids`` of ``level`` with ``ghosts`` cells around it, read
        from ``U`` and the domain's boundary rules."""
        src = sources(self.layout, level, block_origins(self.layout, level, ids, -ghosts),
                      self.layout.block + 2 * ghosts)
        return gathered(U, src, imposed)

    # --- between levels --------------------------------------------------------------------------------
    def _footprint_cells(self, fine: int, ids):
        """Flat storage indices, on the coarser level, of the cells under the
        fine blocks ``ids`` (one array per block, laid out like a half block)."""
        lay, half = self.layout, self.layout.block // 2
        coords = coords_of(ids, lay.blocks(fine), jnp)
        cells = [c * half for c in coords]  # the footprint's first coarse cell per axis
        return _cell_index(lay, fine - 1, cells, half)

    def restricted_into(self, U_coarse, U_fine, fine: int, ids, count):
        """``U_coarse`` with the cells under the first ``count`` fine blocks
        of the list ``ids`` set to the means of their children."""
        def restrict(chunk, U_coarse):
            index = self._footprint_cells(fine, chunk)
            volumes = None
            if self.radial:
                volumes = self.tables[fine].volumes_at(self.radii(fine, chunk))
                volumes = volumes if self.layout.dim == 1 else volumes[:, None, :]
            if self.open_fractions is not None:
                kappa = jnp.asarray(self.open_fractions[fine])[chunk]
                volumes = kappa if volumes is None else kappa * volumes
            if volumes is None:
                means = [jax.vmap(restricted)(a[chunk]) for a in U_fine]
            else:
                means = [jax.vmap(restricted)(a[chunk], volumes) for a in U_fine]
            return tuple(c.ravel().at[index].set(m, mode="drop").reshape(c.shape) for c, m in zip(U_coarse, means))

        return over_chunks(ids, count, restrict, U_coarse, self.layout.cells_per_block)

    def _coarse_windows(self, U_coarse, old_coarse, theta, fine: int, ids, imposed=None):
        """The coarse footprints of the fine blocks ``ids`` with one cell
        around, at ``(1 − θ) old + θ U`` (``old`` None: ``U`` alone), and
        per parent along x the shift of its children's offsets (None when
        planar: :func:`~partmesh.gridref.amr.transfer.volume_shift`)."""
        lay, half = self.layout, self.layout.block // 2
        coords = coords_of(ids, lay.blocks(fine), jnp)
        src = sources(lay, fine - 1, tuple(c * half - 1 for c in coords), half + 2)
        window = gathered(U_coarse, src, imposed)
        if old_coarse is not None:
            before = gathered(old_coarse, src, imposed)
            window = tuple((1.0 - theta) * b + theta * a for a, b in zip(window, before))
        if not self.radial:
            return window, None
        volumes = self.tables[fine].volumes_at(self.radii(fine, ids))
        return window, volume_shift(volumes[:, 0::2], volumes[:, 1::2])

    def _prolonged(self, window, shift):
        """The children of the interior cells of a batch of coarse windows
        (batched with vmap: tiled side by side, 2.3x slower on these small
        windows, measured)."""
        if shift is None:
            return jax.vmap(lambda w: prolonged(w, self.admissible))(window)
        return jax.vmap(lambda w, c: prolonged(w, self.admissible, c))(window, shift)

    def prolonged_blocks(self, U_coarse, old_coarse, theta, fine: int, ids, imposed=None):
        """The fine blocks ``ids`` prolonged from the coarser level, whose
        state is ``(1 − θ) old + θ U`` (``old`` None: ``U`` alone)."""
        return self._prolonged(*self._coarse_windows(U_coarse, old_coarse, theta, fine, ids, imposed))

    def _rims(self):
        """The parts of a block's rim of ``RIM`` fine cells, each ``(coarse
        window, fine cells)``: per axis (x first) a slice of the coarse
        window (one cell around the footprint) and the slice of the block's
        cells its interior's children fill. 2D: the rows along y's two sides,
        then the columns along x's sides between them; 1D: the two ends."""
        half, r = self.layout.block // 2, RIM // 2
        lo, hi = (slice(0, r + 2), slice(0, RIM)), (slice(half - r, half + 2), slice(2 * half - RIM, 2 * half))
        whole, inner = (slice(0, half + 2), slice(0, 2 * half)), (slice(r, half + 2 - r), slice(RIM, 2 * half - RIM))
        if self.layout.dim == 1:
            return (lo,), (hi,)
        return (whole, lo), (whole, hi), (lo, inner), (hi, inner)

    def rims_filled(self, U_fine, U_coarse, old_coarse, theta, fine: int, ids, count, imposed=None):
        """``U_fine`` with the rims of its first ``count`` blocks of the list
        ``ids`` (the cells within :data:`RIM` of a side: all that the windows
        of their active neighbours read) prolonged from the coarser level, as
        :meth:`prolonged_blocks` would fill them; their inner cells are left
        as they are (no window reads them)."""
        if self.layout.block <= 2 * RIM:
            return self.filled(U_fine, U_coarse, old_coarse, theta, fine, ids, count, imposed)

        def fill(chunk, U):
            window, shift = self._coarse_windows(U_coarse, old_coarse, theta, fine, chunk, imposed)
            for part in self._rims():
                coarse = (slice(None),) + tuple(c for c, _ in part[::-1])  # (laid out ([y,] x))
                cells = (chunk,) + tuple(f for _, f in part[::-1])
                x = part[0][0]  # the parents' shifts along x: those of the part's interior columns
                children = self._prolonged(tuple(w[coarse] for w in window),
                                           None if shift is None else shift[:, x.start:x.stop - 2])
                U = tuple(u.at[cells].set(c, mode="drop") for u, c in zip(U, children))
            return U

        return over_chunks(ids, count, fill, U_fine, self.layout.cells_per_block)

    def refluxed(self, U_coarse, flux_coarse, register, maps_fine, fine: int, ids, count):
        """``U_coarse`` with every coarse cell next to a fine block of ``ids``
        (across a face whose fine neighbour is not active) corrected by the
        fine fluxes summed over the pair of fine steps, in place of its own
        (Berger & Colella 1989, §3.4). Of revolution, the two fine faces
        over a coarse face normal to z weigh as their cells' volumes, and a
        correction through a face normal to r is weighted by its area over
        the coarse cell's volume."""
        lay, half = self.layout, self.layout.block // 2
        nb_f, cells_c = lay.blocks(fine), lay.cells(fine - 1)
        dx_c = lay.spacing(fine - 1)
        coords = coords_of(ids, nb_f, jnp)
        valid = jnp.arange(ids.shape[0]) < count
        lanes = jnp.arange(half)
        for d in range(lay.dim):
            for side in (0, 1):
                neighbour = list(coords)
                step = 1 if side else -1
                n_d = nb_f[d]
                beyond = coords[d] + step
                inside = (beyond >= 0) & (beyond < n_d)
                if lay.periodic[d]:
                    beyond, inside = jnp.mod(beyond, n_d), jnp.ones_like(inside)
                neighbour[d] = jnp.clip(beyond, 0, n_d - 1)
                open_ = valid & inside & ~maps_fine.ravel()[flat_id(neighbour, nb_f)]
                # the coarse face and the coarse cell beyond it, along d
                face = (coords[d] + side) * half
                cell = jnp.mod(face if side else face - 1, cells_c[d])
                face = jnp.mod(face, cells_c[d])
                fine_sum = [r[:, side] for r in register[d]]  # (n[, B]) per variable
                if lay.dim == 2:
                    other = 1 - d
                    along = coords[other][:, None] * half + lanes[None, :]
                    if self.radial and d == 1:  # the two fine faces' areas: their cells' volumes
                        v = self.tables[fine].volumes_at(2 * along[:, :, None] + jnp.arange(2))
                        w = v / jnp.sum(v, axis=-1, keepdims=True)
                        fine_sum = [w[..., 0] * f[:, 0::2] + w[..., 1] * f[:, 1::2] for f in fine_sum]
                    else:
                        fine_sum = [0.5 * (f[:, 0::2] + f[:, 1::2]) for f in fine_sum]  # two fine faces a coarse face
                    at = [None, None]
                    at[d], at[other] = jnp.broadcast_to(face[:, None], along.shape), along
                    coarse_flux = _face_values(lay, fine - 1, flux_coarse[d], d, at)
                    target = [None, None]
                    target[d], target[other] = jnp.broadcast_to(cell[:, None], along.shape), along
                    index = lay.cell_index(fine - 1, target)
                    mask = open_[:, None]
                else:
                    coarse_flux = _face_values(lay, fine - 1, flux_coarse[d], d, [face])
                    index = lay.cell_index(fine - 1, [cell])
                    mask = open_
                sign = (1.0 if side else -1.0) / dx_c[d]
                if self.radial and d == 0:  # the face's area over the coarse cell's volume
                    table = self.tables[fine - 1]
                    sign = sign * table.areas_at(face) / table.volumes_at(cell)
                    sign = sign[:, None] if lay.dim == 2 else sign
                index = jnp.where(mask, index, U_coarse[0].size)
                U_coarse = tuple(u.ravel().at[index].add(sign * (f - c), mode="drop").reshape(u.shape)
                                 for u, f, c in zip(U_coarse, fine_sum, coarse_flux))
        return U_coarse

    def filled(self, U_fine, U_coarse, old_coarse, theta, fine: int, ids, count, imposed=None):
        """``U_fine`` with its first ``count`` blocks of the list ``ids``
        prolonged from the coarser level (:meth:`prolonged_blocks`), a
        chunk of blocks at a time."""
        def fill(chunk, U):
            return self.with_blocks(U, chunk, self.prolonged_blocks(U_coarse, old_coarse, theta, fine, chunk,
                                                                    imposed))

        return over_chunks(ids, count, fill, U_fine, self.layout.cells_per_block)

    def halo_filled(self, H: Hierarchy, fine: int, theta, imposed=None) -> Hierarchy:
        """``H`` with the halo blocks of level ``fine`` prolonged from the
        coarser level at ``(1 − θ) old + θ U`` (θ = 1: ``U`` alone)."""
        ids, count = H.halo[fine]
        old = None if isinstance(theta, float) and theta == 1.0 else H.old[fine - 1]
        U = self.rims_filled(H.U[fine], H.U[fine - 1], old, theta, fine, ids, count, imposed)
        return H._replace(U=with_level(H.U, fine, U))

    # --- regridding ------------------------------------------------------------------------------------
    def flags(self, U, level: int, ids, count, imposed=None):
        """``(refine, keep)``: block maps of ``level + 1`` whose footprint on
        ``level`` holds a cell whose estimates pass ``refine`` or
        ``gradient`` (to keep: those times ``derefine / refine``), read on
        the first ``count`` active blocks ``ids``, a chunk at a time."""
        lay = self.layout
        nb = lay.blocks(level + 1)
        size = int(np.prod(nb))
        offsets = jnp.arange(2)
        thresholds = (1.0, self.derefine / self.refine)

        def flag(chunk, hits):
            window = self.windows(U, level, chunk, 1, imposed)
            jumps, slopes = 0.0, 0.0
            for q in self.sensed(window):  # (batched with vmap: as fast as tiled side by side, measured)
                jumps = jnp.maximum(jumps, jax.vmap(lohner)(q))
                slopes = jnp.maximum(slopes, jax.vmap(variation)(q))
            # the estimate relative to its threshold: above 1 asks for refinement
            estimate = jnp.maximum(jumps / self.refine, slopes / self.gradient)
            children = jax.vmap(child_maxima)(estimate)  # (n, 2[, 2]) laid out ([cy,] cx)
            valid = (chunk < lay.n_blocks(level)).reshape((-1,) + (1,) * lay.dim)  # (the list's padding is not)
            coords = coords_of(chunk, lay.blocks(level), jnp)
            if lay.dim == 1:
                child = (2 * coords[0][:, None] + offsets[None, :],)
            else:
                child = (2 * coords[0][:, None, None] + offsets[None, None, :],
                         2 * coords[1][:, None, None] + offsets[None, :, None])
            index = jnp.where(valid, flat_id(child, nb), size)
            return tuple(hit.at[index].set(children > threshold, mode="drop")
                         for hit, threshold in zip(hits, thresholds))

        hits = over_chunks(ids, count, flag, (jnp.zeros(size, bool),) * 2, lay.cells_per_block)
        return tuple(hit.reshape(nb[::-1]) for hit in hits)

    def regridded(self, H: Hierarchy, imposed=None, forced: tuple | None = None,
                  fill: bool = True, due=True) -> tuple[Hierarchy, jnp.ndarray]:
        """``(H', short)``: every level's blocks set anew from the error
        estimates of the level below (``forced[l]``: a block map of level
        ``l`` that must be active, or None), the new blocks prolonged from
        the level below (unless not ``fill``: the caller sets them);
        ``short`` is True (and ``H'`` is ``H`` with ``need`` set) when a
        block list is too short for them. Where the traced ``due`` is False,
        ``H'`` is ``H`` (every loop of the regrid runs no pass)."""
        lay, L = self.layout, self.layout.levels
        due = jnp.asarray(due, bool)
        # the block lists as the estimator reads them: empty unless due, so that its loops run no pass
        read = H._replace(**{f: tuple((ids, jnp.where(due, count, 0)) for ids, count in getattr(H, f))
                             for f in ("active", "halo")})
        for level in range(1, L - 1):  # the estimator reads one ghost layer: the halos, filled now
            read = self.halo_filled(read, level, 1.0, imposed)
        H = H._replace(U=read.U)
        maps = [H.maps[0]]
        for level in range(L - 1):
            ids, count = read.active[level]
            high, low = self.flags(H.U[level], level, ids, count, imposed)
            want = (blockmaps.dilated(high, lay.periodic, self.buffer)
                    | (H.maps[level + 1] & blockmaps.dilated(low, lay.periodic, self.buffer)))
            if forced is not None and forced[level + 1] is not None:
                want = want | forced[level + 1]
            maps.append(want)
        for level in range(L - 1, 1, -1):  # proper nesting, finest first
            maps[level - 1] = maps[level - 1] | blockmaps.parents(blockmaps.dilated(maps[level], lay.periodic, 2))
        active, halo, need = [H.active[0]], [H.halo[0]], [H.need[0]]
        short = jnp.zeros((), bool)
        for level in range(1, L):
            cap, cap_halo = H.active[level][0].shape[0], H.halo[level][0].shape[0]
            a = blockmaps.listed(maps[level], cap)
            h = blockmaps.listed(blockmaps.dilated(maps[level], lay.periodic) & ~maps[level], cap_halo)
            active.append(a)
            halo.append(h)
            need.append(jnp.stack([a[1], h[1]]))
            short = short | (a[1] > cap) | (h[1] > cap_halo)
        need = jnp.where(due, jnp.stack(need), H.need)
        short = short & due
        unchanged = short | ~due  # (the lists, maps and blocks of H kept)

        # the new blocks prolonged, unless a list is short (then none: the step halts, the lists grow and the
        # regrid is made again); chosen by selects on the lists and trip counts, not by a conditional, whose
        # branches would copy every level's storage in and out
        U = list(H.U)
        for level in range(1, L if fill else 1):
            fresh = maps[level] & ~H.maps[level]
            ids, count = blockmaps.listed(fresh, active[level][0].shape[0])
            U[level] = self.filled(U[level], U[level - 1], None, 1.0, level, ids, jnp.where(unchanged, 0, count),
                                   imposed)
        counts = jnp.stack([a[1] for a in active])
        peak = jnp.maximum(H.peak, jnp.concatenate([counts, jnp.sum(counts, dtype=jnp.int32)[None]]))

        def kept(new, old):
            return jax.tree_util.tree_map(lambda a, b: jnp.where(unchanged, b, a), new, old)

        H = H._replace(U=tuple(U), active=kept(tuple(active), H.active), halo=kept(tuple(halo), H.halo),
                       maps=kept(tuple(maps), H.maps), need=need, peak=kept(peak, H.peak))
        return H, short


def _coarsened(finest, lay: Layout) -> list:
    """Per level, the means over every level's cells of the finest level's
    block-major field ``finest`` (each coarser cell the mean of its children)."""
    L, B = lay.levels, lay.block
    fields = [np.asarray(finest)]
    for level in range(L - 1, 0, -1):
        fine = fields[0]
        nbx, nby = lay.blocks(level)
        whole = fine.reshape(nby, nbx, B, B).transpose(0, 2, 1, 3).reshape(nby * B, nbx * B)
        coarse = whole.reshape(nby * B // 2, 2, nbx * B // 2, 2).mean(axis=(1, 3))
        cx, cy = lay.blocks(level - 1)
        fields.insert(0, coarse.reshape(cy, B, cx, B).transpose(0, 2, 1, 3).reshape(-1, B, B))
    return fields


def _cell_index(lay: Layout, level: int, first, n: int):
    """Flat storage indices of the ``n``-cell squares starting at the global
    cells ``first`` (per axis, x first, each (m,)) of ``level``: (m, n[, n])."""
    lanes = jnp.arange(n)
    if lay.dim == 1:
        return lay.cell_index(level, [first[0][:, None] + lanes[None, :]])
    x = first[0][:, None, None] + lanes[None, None, :]
    y = first[1][:, None, None] + lanes[None, :, None]
    return lay.cell_index(level, [x, y])


def _face_values(lay: Layout, level: int, flux_d, d: int, at):
    """Per variable, the stored flux through the face normal to axis ``d``
    at global face indices ``at`` (the face's index along ``d``, the cell's
    along the others), read from the block holding the cell on its high
    side (its low face)."""
    B = lay.block
    if lay.dim == 1:
        face = at[0]
        index = (face // B) * (B + 1) + face % B
        return [f.ravel()[index] for f in flux_d]
    x, y = at
    nbx = lay.blocks(level)[0]
    block = (y // B) * nbx + x // B
    if d == 0:  # x faces: (B rows, B + 1 faces)
        index = block * (B * (B + 1)) + (y % B) * (B + 1) + x % B
    else:  # y faces: (B + 1 faces, B columns)
        index = block * ((B + 1) * B) + (y % B) * B + x % B
    return [f.ravel()[index] for f in flux_d]
