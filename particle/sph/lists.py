"""Neighbour lists of a particle set with its mirror ghosts, kept and reused
while they still hold every pair that can interact (a Verlet list with a
skin: Verlet 1967; Monaghan 2005 §7). Shared by the gas SPH (``sph``) and
the water SPH (``wcsph``)."""

from __future__ import annotations

import dataclasses
import time as _time
from dataclasses import dataclass

import numpy as np

from partmesh.particle.cell_grid import cell_support, nearby_maximum
from partmesh.particle.neighbours import neighbour_lists, renumbered
from partmesh.particle.pair_geometry import periods
from partmesh.particle.sph.particles import mirror_ghosts, mirror_images


class PerParticle:
    """Mixin of dataclasses whose every field holds one entry per particle:
    :meth:`take` reorders (or picks) them all at once."""

    def take(self, order):
        """The same record with its particles in the order ``order`` (indices)."""
        return type(self)(*(getattr(self, f.name)[order] for f in dataclasses.fields(self)))


@dataclass
class NeighbourLists:
    """CSR neighbour lists of the ``n`` fluid particles, whose neighbours
    are fluid particles, the imposed ones after them and their mirror
    ghosts (``src``: each ghost's source, ``sides``: the mask of the sides
    it is mirrored across; imposed particles and ghosts have empty lists of
    their own: their sums are not needed), with the positions ``x`` and
    velocities ``v`` of all of them and the radius each particle's list is
    complete for."""

    n: int
    x: np.ndarray
    v: np.ndarray
    src: np.ndarray
    sides: np.ndarray
    radius: np.ndarray
    offsets: np.ndarray
    index: np.ndarray

    def take(self, order) -> "NeighbourLists":
        """The same lists with the fluid particles in the order ``order``
        (the imposed particles and the ghosts keep their places)."""
        full = np.concatenate([order, np.arange(self.n, self.x.shape[0])])
        new_id = np.empty_like(full)
        new_id[full] = np.arange(full.size)
        offsets, index = renumbered(self.offsets, self.index, full)
        return NeighbourLists(self.n, self.x[full], self.v[full], new_id[self.src], self.sides, self.radius[full],
                              offsets, index)


class VerletLists:
    """The neighbour lists of one run. ``walls`` names the sides ghosts are
    mirrored across (an object with ``sides``, ``boundaries`` and
    ``domain``, as a scene: :func:`partmesh.particle.sph.particles.mirror_ghosts`),
    ``open_`` the outflow sides mirrored with the velocity kept; ``lo``,
    ``hi`` and ``periodic`` the search box. ``searches`` counts the
    searches made and ``seconds`` the wall time spent on lists."""

    def __init__(self, walls, lo, hi, periodic, open_=()):
        self.walls, self.open = walls, tuple(open_)
        self.lo, self.hi, self.periodic = np.asarray(lo, float), np.asarray(hi, float), np.asarray(periodic, bool)
        self.box, self.half = periods(self.lo, self.hi, self.periodic, self.lo.size)
        #: the widest list the periodic axes allow (minimum images)
        self.half_period = 0.5 * float(np.min((self.hi - self.lo)[self.periodic])) if self.periodic.any() else np.inf
        self.searches, self.seconds, self.last = 0, 0.0, None

    def lists(self, x_real, v_real, H_real, n, slack) -> NeighbourLists:
        """Lists of the real particles (``n`` fluid, then imposed ones) and
        their ghosts complete for the supports ``H_real``: the last ones at
        the moved positions if :meth:`reusable`, else a new search for
        ``slack`` times the supports."""
        return self.reusable(x_real, v_real, H_real, n) or self.search(x_real, v_real, H_real, n, slack)

    def search(self, x_real, v_real, H_real, n, slack, growth=None) -> NeighbourLists:
        """Mirror ghosts and neighbour lists of the real particles and their
        ghosts, complete for ``slack`` times the supports ``H_real`` (times
        ``growth``, the growth of the first supports expected before the
        lists are renewed), plus a skin for motion: particle i gets
        ``(slack − 1) median(H) |v_i|/max|v|`` more, so the fastest, which
        use up the skin first (:meth:`reusable`), get twice the skin of the
        typical particle; kept for reuse."""
        t0 = _time.perf_counter()
        speed = np.sqrt(np.einsum("ij,ij->i", v_real, v_real))
        fastest = float(speed.max()) if speed.size else 0.0
        moving = (slack - 1.0) * float(np.median(H_real)) * (speed / fastest if fastest > 0.0 else 0.0 * speed)
        reach = slack * H_real + moving
        if growth is not None:
            reach[: growth.size] *= growth
        reach = np.minimum(reach, self.half_period)  # (minimum images: no list reaches beyond half a period)
        gx, gv, src, sides = mirror_ghosts(self.walls, x_real, v_real, reach, self.open)
        x = np.concatenate([x_real, gx])
        radius = np.concatenate([reach, reach[src]])
        offsets, index = neighbour_lists(x, radius, self.lo, self.hi, self.periodic, rows=n)
        self.last = NeighbourLists(n, x, np.concatenate([v_real, gv]), src, sides, radius, offsets, index)
        self.searches += 1
        self.seconds += _time.perf_counter() - t0
        return self.last

    def reusable(self, x_real, v_real, H_real, n) -> NeighbourLists | None:
        """The last lists at the moved positions, if they still hold every
        pair that can interact (Verlet 1967): a pair i, j apart by r now was
        apart by at most r + |δ_i − δ_j| when they were built (δ: a
        particle's displacement since), so particle i's list is still
        complete for the radius R_i − max |δ_i − δ_j| over the j now within
        H_i of it (R_i: the radius it was built for). Usable when the
        particle count is the same and every support is below that radius.
        The displacements of the j near i are bounded component by component
        by |δ_i| + max |δ| (cheap, and enough most steps) and, where that is
        not enough, by the range over the cells around i
        (:func:`~partmesh.particle.cell_grid.nearby_maximum`; the range of all for
        the few supports wider than the cells), so gas that streams as a
        whole, as at an inlet, keeps its lists, and a fast stream does not
        use up the skin of the slow gas far from it. Positions are compared
        index by index, so a re-sort or a jump of an inflow buffer shows as
        a large displacement and forces a new search."""
        lists = self.last
        if lists is None or lists.n != n or lists.x.shape[0] != x_real.shape[0] + lists.src.size:
            return None
        t0 = _time.perf_counter()
        gx, gv = mirror_images(self.walls, x_real, v_real, lists.src, lists.sides, self.open)
        x = np.concatenate([x_real, gx])
        moved = x - lists.x
        for a in np.flatnonzero(self.periodic):
            moved[:, a] -= self.box[a] * np.round(moved[:, a] / self.box[a])
        H = np.concatenate([H_real, H_real[lists.src]])
        # |δ_i − δ_j| ≤ |δ_i| + max |δ|: enough most steps, and cheap
        shift = np.sqrt(np.einsum("ij,ij->i", moved, moved))
        radius = lists.radius - shift - shift.max()
        usable = np.all(H < radius)
        if not usable:  # the ranges near i, where |δ_i| + max |δ| is not enough
            cells = cell_support(H)
            span = nearby_maximum(x, np.concatenate([moved, -moved], axis=1), self.lo, self.hi, self.periodic, cells)
            span[H > cells] = np.concatenate([moved.max(axis=0), -moved.min(axis=0)])
            dim = moved.shape[1]
            apart = np.maximum(span[:, :dim] - moved, moved + span[:, dim:])  # max |δ_i − δ_j| per axis
            radius = np.maximum(radius, lists.radius - np.sqrt(np.einsum("ij,ij->i", apart, apart)))
            usable = np.all(H < radius)
        self.seconds += _time.perf_counter() - t0
        return dataclasses.replace(lists, x=x, v=np.concatenate([v_real, gv]), radius=radius) if usable else None

    def wrapped(self, x):
        """Positions ``x`` with the periodic axes wrapped back into the box (in place)."""
        for d in np.flatnonzero(self.periodic):
            x[:, d] = self.lo[d] + np.mod(x[:, d] - self.lo[d], self.hi[d] - self.lo[d])
        return x

    def renumber(self, order):
        """Follow the fluid particles into the order ``order`` (the kept
        lists with them: a re-sort costs no search)."""
        if self.last is not None and self.last.n == order.size:
            self.last = self.last.take(order)

    def forget(self):
        """Drop the kept lists (the next call searches)."""
        self.last = None
