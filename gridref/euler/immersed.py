"""Conservative cut-cell immersed boundaries from the scene's
signed-distance shapes.

Every cell has the volume fraction κ open to the gas and every face the
aperture α (its open fraction), both from the shapes' signed distance
sampled inside the cell and along the face. A cell's conserved state
changes by its fluxes through the open parts of its faces and by the
pressure of the wall inside it (Colella, Graves, Keen & Modiano 2006,
J. Comput. Phys. 211, 347):

    κ V dU/dt = −Σ_f α_f A_f F_f − (0, p_w B, 0),   B = −Σ_f α_f A_f n_f,

where ``B`` (the wall's length times its normal into the solid) closes the
cell's faces, so a gas at rest stays at rest to round-off, and p_w is the
momentum flux of the Riemann problem between the cell's half-step state
and its mirror image across the wall (a slip wall). No mass or energy
crosses a wall.

In the r–z plane of an axisymmetric run the faces are rings (areas
``α a_f A_f``, volumes ``κ v`` with the ring factors of
:mod:`partmesh.gridref.revolution`) and the wall vector closes the cell
against the hoop source of its open part as well,
``B/V = κ g e_r − Σ_f α_f a_f A_f n_f / V``; the wall's Riemann problem
takes the wall's own normal (that of the planar closure). Redistribution
and merging weigh every cell by its volume ``κ w`` (``w`` = 2π r_c).

Small cells would limit the time step; flux redistribution keeps the
regular cells' step. With the conservative divergence D^C = D/κ (D the
right-hand side per full cell volume) and its κ-weighted average over the
3 × 3 neighbourhood, D^NC = Σ κ D^C / Σ κ, a cut cell advances with
D^H = κ D^C + (1 − κ) D^NC and the rest, δ = κ (1 − κ)(D^C − D^NC) per unit
volume, goes to its open neighbours in proportion to their volume
(Chern & Colella 1987; Pember et al. 1995, J. Comput. Phys. 120, 278):
mass, momentum and energy are conserved to round-off.

Flux redistribution alone does not keep a small cell's pressure positive
behind a strong shock, so every cell with κ < ``MIX`` is also merged with
the open neighbour of largest κ after each step: the group takes its
volume-weighted mean state, Σ κ U / Σ κ (the conservative mixing of Hu,
Khoo, Adams & Huang 2006, J. Comput. Phys. 219, 553).

Solid cells (κ = 0) within ``band`` cells of the surface are ghost cells
for the reconstruction: their primitive state is the gas state at the image
point mirrored across the surface, ``x_I = x_G + 2|φ(x_G)| n``, bilinearly
interpolated from open cells, with the normal velocity reversed
(Mittal & Iaccarino 2005). Deeper solid cells keep a fixed harmless state.
"""

from __future__ import annotations

from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.cases.shape_queries import normal, signed_distance
from partmesh.gridref.euler.riemann import RIEMANN_SOLVERS
from partmesh.gridref.grid import bilinear_stencil, mesh
from partmesh.gridref.revolution import cell_volumes, face_areas, hoop, revolved

#: sub-samples per cell side (volume fractions) and per face (apertures)
SAMPLES = 16
#: cut cells with less open volume than this are closed (κ = 0): a sliver
#: the flow could not resolve, kept out of the divisions by κ
KAPPA_MIN = 1e-3
#: cut cells with less open volume than this are merged with a larger neighbour
MIX = 0.5


@dataclass(frozen=True)
class ImmersedBoundary:
    """Cut-cell geometry and ghost-cell gather tables of one 2D grid."""

    shape: tuple[int, ...]  # field layout (ny, nx)
    volume: np.ndarray  # (ny, nx) κ, the open volume fraction
    solid: np.ndarray  # (ny, nx) cell centres inside a body (the output's solid mask)
    apertures: tuple[np.ndarray, np.ndarray]  # α of the x faces (ny, nx+1) and y faces (ny+1, nx)
    cut: np.ndarray  # flat indices of the cells holding a piece of wall
    wall: np.ndarray  # (2, n_cut) B/V: the wall vector that closes each cut cell, per full cell volume
    wall_normal: np.ndarray  # (2, n_cut) the unit normal of each cut cell's wall, into the solid
    ghost: np.ndarray  # flat indices of ghost cells
    stencil: np.ndarray  # (n_ghost, 4) flat indices of the image-point stencil
    weights: np.ndarray  # (n_ghost, 4), zero on solid cells, rows sum to 1
    normal: np.ndarray  # (2, n_ghost) outward unit normals
    periodic: tuple[bool, bool]  # along x, y
    group: np.ndarray  # flat index of the cell each cell is merged into (itself if none)
    weight: np.ndarray | float = 1.0  # (ny, nx) each cell's full volume relative to a planar cell's (2π r_c in r–z)

    @property
    def fluid(self) -> np.ndarray:
        """Cells open to the gas."""
        return self.volume > 0.0

    def fill(self, W):
        """The primitive state ``W`` (tuple) with every ghost cell set from
        its image point."""
        image = mirrored_images(tuple(a.ravel()[self.stencil] for a in W), self.weights, self.normal)
        return tuple(a.ravel().at[self.ghost].set(g).reshape(a.shape) for a, g in zip(W, image))

    def reset(self, U, U_solid):
        """``U`` with the solid cells put back to ``U_solid``."""
        return tuple(jnp.where(self.fluid, a, b) for a, b in zip(U, U_solid))

    def wall_divergence(self, W, gamma, riemann):
        """The walls' part of D, per full cell volume: ``(0, p_w B/V, 0)``
        in every cut cell, with ``p_w`` the normal momentum flux of the
        Riemann problem between the cell's primitive state ``W`` and its
        mirror image across the wall."""
        p_wall = wall_pressure(tuple(a.ravel()[self.cut] for a in W), self.wall_normal, gamma, riemann)
        zero = jnp.zeros(self.shape)
        return (zero, *(zero.ravel().at[self.cut].set(p_wall * b).reshape(self.shape) for b in self.wall), zero)

    def advanced(self, U, divergence, dt):
        """``U − Δt D^H`` with the redistributed remainder of every cut cell
        added to its neighbours, from the right-hand side ``divergence``
        (per full cell volume, apertures and walls included).

        The sums run over the few cells they concern (:attr:`redistribution`):
        every other open cell advances with ``U − Δt D`` (there κ = 1 and no
        neighbour gives a share, so D^H = D), a solid cell keeps its state."""
        givers, giver_nb, band, band_nb = self.redistribution
        kappa_g, around_g, others_g = self.open_volumes(givers, giver_nb)
        kappa_b, around_b, others_b = self.open_volumes(band, band_nb)
        weight_g = np.broadcast_to(self.weight, self.shape).ravel()[givers]
        open_ = jnp.asarray(self.fluid)
        out = []
        for u, D in zip(U, divergence):
            Dw = D * self.weight  # (the volumes: κ w of a cell of weight w)
            average = band_sum(Dw, giver_nb) / np.where(around_g > 0.0, around_g, 1.0)  # Σ κ w D^C / Σ κ w
            deficit = jnp.where(others_g > 0.0, (1.0 - kappa_g) * (D.ravel()[givers] - kappa_g * average) * weight_g,
                                0.0)
            shares = jnp.zeros(D.size).at[givers].set(deficit / np.where(others_g > 0.0, others_g, 1.0))
            average = band_sum(Dw, band_nb) / np.where(around_b > 0.0, around_b, 1.0)
            D_band = D.ravel()[band]
            hybrid = jnp.where(others_b > 0.0, D_band + (1.0 - kappa_b) * average,
                               D_band / np.where(kappa_b > 0.0, kappa_b, 1.0))
            gained = band_sum(shares.reshape(D.shape), band_nb) - shares[band]
            far = jnp.where(open_, u - dt * D, u)
            out.append(far.ravel().at[band].set(u.ravel()[band] - dt * (hybrid + gained)).reshape(u.shape))
        return self.mixed(tuple(out))

    def open_volumes(self, cells, neighbours):
        """At ``cells``: κ, the open volume Σ κ w over their 3 × 3
        neighbourhoods, and that of the neighbours alone."""
        kappa = self.volume.ravel()[cells]
        volume = self.volume * self.weight
        around = band_sum(volume, neighbours, np)
        return kappa, around, around - volume.ravel()[cells]

    @property
    def redistribution(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(givers, their neighbours, band, its neighbours)``: the cells
        that give a share of their remainder (κ < 1 with open volume
        around them: cut cells and closed slivers), and the open cells
        whose update differs from ``U − Δt D`` (κ < 1, or a giver among
        their 3 × 3 neighbours), as flat indices, each with the flat
        indices of its neighbourhood (:func:`neighbourhoods`)."""
        around = _box_sum(self.volume, self.periodic)
        givers = (self.volume < 1.0) & (around - self.volume > 0.0)
        near = _box_sum(givers.astype(float), self.periodic) > 0.0
        giving = np.flatnonzero(givers.ravel())
        band = np.flatnonzero(self.fluid.ravel() & (near | (self.volume < 1.0)).ravel())
        return giving, neighbourhoods(giving, self.shape, self.periodic), band, neighbourhoods(band, self.shape,
                                                                                             self.periodic)

    def mixed(self, U):
        """``U`` with every merged group of cells set to its mean, Σ κ w U / Σ κ w."""
        members, label = self.merged
        if members.size == 0:
            return U
        kappa = (self.volume * self.weight).ravel()[members]
        n_groups = int(label.max()) + 1
        volume = np.bincount(label, weights=kappa, minlength=n_groups)
        out = []
        for u in U:
            flat = u.ravel()
            total = jax.ops.segment_sum(kappa * flat[members], label, n_groups)
            out.append(flat.at[members].set((total / volume)[label]).reshape(u.shape))
        return tuple(out)

    @property
    def merged(self) -> tuple[np.ndarray, np.ndarray]:
        """``(cells, label)``: the flat indices of the cells in groups of
        more than one, and their group numbered from 0."""
        size = np.bincount(self.group, minlength=self.group.size)
        members = np.flatnonzero(size[self.group] > 1)
        _, label = np.unique(self.group[members], return_inverse=True)
        return members, label


def mirrored_images(W_stencil, weights, normal):
    """The primitive state at the ghost cells' image points, bilinear from
    the states ``W_stencil`` (per variable, (n_ghost, 4)) of their stencils
    with ``weights``, the velocity's component along the outward ``normal``
    reversed (Mittal & Iaccarino 2005)."""
    image = [jnp.sum(a * weights, axis=-1) for a in W_stencil]
    vn = image[1] * normal[0] + image[2] * normal[1]
    image[1] = image[1] - 2.0 * vn * normal[0]
    image[2] = image[2] - 2.0 * vn * normal[1]
    return image


def wall_pressure(W, wall_normal, gamma, riemann):
    """The normal momentum flux of the Riemann problem between the primitive
    state ``W`` = (ρ, u, v, p) and its mirror image across a wall of unit
    normal ``wall_normal`` (a slip wall)."""
    rho, u, v, p = W
    nx, ny = wall_normal
    un, ut = u * nx + v * ny, v * nx - u * ny
    return RIEMANN_SOLVERS[riemann]((rho, un, ut, p), (rho, -un, ut, p), gamma)[1]


def neighbourhoods(cells, shape, periodic) -> np.ndarray:
    """Per flat cell index in ``cells`` of a ``shape`` = (ny, nx) grid, the
    flat indices of its 3 × 3 neighbourhood as ``[dx][dy]``, dx, dy = −1,
    0, 1: wrapped along periodic axes (``periodic`` along x, y), and beyond
    another side the index one past the last cell, which
    :func:`band_sum` reads as 0."""
    ny, nx = shape
    iy, ix = np.divmod(cells, nx)
    out = np.empty((len(cells), 3, 3), np.int64)
    for a, dx in enumerate((-1, 0, 1)):
        for b, dy in enumerate((-1, 0, 1)):
            x, y, inside = ix + dx, iy + dy, np.ones(len(cells), bool)
            if periodic[0]:
                x = x % nx
            else:
                inside &= (x >= 0) & (x < nx)
            if periodic[1]:
                y = y % ny
            else:
                inside &= (y >= 0) & (y < ny)
            out[:, a, b] = np.where(inside, y * nx + x, ny * nx)
    return out


def band_sum(a, neighbours, xp=jnp):
    """:func:`_box_sum` of the field ``a`` at the cells whose neighbourhoods
    ``neighbours`` lists (:func:`neighbourhoods`), added in the same order:
    each column of three first, then the columns."""
    values = xp.concatenate([xp.ravel(a), xp.zeros(1, a.dtype)])[neighbours]
    columns = [(values[:, k, 0] + values[:, k, 1]) + values[:, k, 2] for k in range(3)]
    return (columns[0] + columns[1]) + columns[2]


def _box_sum(a, periodic):
    """Sum over each cell's 3 × 3 neighbourhood (itself included): wrapped
    along periodic axes, zero beyond the other sides."""
    for axis, wrap in ((0, periodic[1]), (1, periodic[0])):
        width = [(0, 0)] * a.ndim
        width[axis] = (1, 1)
        padded = np.pad(a, width, mode="wrap" if wrap else "constant")
        n = a.shape[axis]
        a = sum(np.take(padded, np.arange(k, k + n), axis=axis) for k in range(3))
    return a


def _open_fraction(shapes, x0, y0, ex, ey, h) -> np.ndarray:
    """Open fraction of squares (``ex``, ``ey`` both 1) or segments (one of
    them 0) of side ``h`` starting at ``(x0, y0)``: exact 0 or 1 where the
    surface is farther than the element's size, else the mean over
    ``SAMPLES`` (per side) evenly spaced points of the gas fraction of each
    point's share, clip(½ + φ/δ, 0, 1) with δ the spacing of the points."""
    x0, y0 = np.asarray(x0, float), np.asarray(y0, float)
    phi = signed_distance(shapes, x0 + 0.5 * h * ex, y0 + 0.5 * h * ey)
    frac = (phi > 0.0).astype(float)
    near = np.abs(phi) < h
    s = (np.arange(SAMPLES) + 0.5) / SAMPLES
    if ex and ey:
        sx, sy = (a.ravel() for a in np.meshgrid(s, s))
    else:
        sx, sy = s * ex, s * ey
    px = x0[near][:, None] + h * sx
    py = y0[near][:, None] + h * sy
    # each sample counts by how much of its own square (strip) lies in the gas, for a straight surface
    frac[near] = np.mean(np.clip(0.5 + signed_distance(shapes, px, py) * (SAMPLES / h), 0.0, 1.0), axis=1)
    return frac


def cut_cells(grid, shapes, periodic=(False, False)):
    """``(κ, α_x, α_y)``: open volume fraction of every cell and aperture of
    every face of the 2D ``grid``; a face of a closed cell is closed, and a
    periodic side's two copies of a face agree."""
    (x_lo, _), (y_lo, _) = grid.domain
    h = grid.step[0]
    nx, ny = grid.shape
    jj, ii = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    kappa = _open_fraction(shapes, x_lo + ii * h, y_lo + jj * h, 1, 1, h)
    kappa[kappa < KAPPA_MIN] = 0.0
    jf, if_ = np.meshgrid(np.arange(ny), np.arange(nx + 1), indexing="ij")
    ax = _open_fraction(shapes, x_lo + if_ * h, y_lo + jf * h, 0, 1, h)
    jf, if_ = np.meshgrid(np.arange(ny + 1), np.arange(nx), indexing="ij")
    ay = _open_fraction(shapes, x_lo + if_ * h, y_lo + jf * h, 1, 0, h)
    open_ = kappa > 0.0
    ax[:, 1:-1] *= open_[:, 1:] & open_[:, :-1]
    ax[:, 0] *= open_[:, 0] & (open_[:, -1] if periodic[0] else True)
    ax[:, -1] *= open_[:, -1] & (open_[:, 0] if periodic[0] else True)
    ay[1:-1] *= open_[1:] & open_[:-1]
    ay[0] *= open_[0] & (open_[-1] if periodic[1] else True)
    ay[-1] *= open_[-1] & (open_[0] if periodic[1] else True)
    if periodic[0]:
        ax[:, 0] = ax[:, -1] = np.minimum(ax[:, 0], ax[:, -1])
    if periodic[1]:
        ay[0] = ay[-1] = np.minimum(ay[0], ay[-1])
    return kappa, ax, ay


def merge_groups(kappa, periodic) -> np.ndarray:
    """The cell every cell's group is named after: a cell with
    0 < κ < ``MIX`` joins its open neighbour (of eight) with the largest κ,
    and linked cells form one group (named after its lowest cell)."""
    ny, nx = kappa.shape
    group = np.arange(kappa.size)
    small = np.flatnonzero((kappa.ravel() > 0.0) & (kappa.ravel() < MIX))
    if small.size == 0:
        return group
    j, i = np.divmod(small, nx)
    best, best_kappa = small.copy(), np.zeros(small.size)
    for dj in (-1, 0, 1):
        for di in (-1, 0, 1):
            jj, ii = j + dj, i + di
            jj = jj % ny if periodic[1] else jj
            ii = ii % nx if periodic[0] else ii
            inside = (jj >= 0) & (jj < ny) & (ii >= 0) & (ii < nx) & ((dj != 0) | (di != 0))
            k = np.where(inside, np.clip(jj, 0, ny - 1) * nx + np.clip(ii, 0, nx - 1), 0)
            better = inside & (kappa.ravel()[k] > best_kappa)
            best[better], best_kappa[better] = k[better], kappa.ravel()[k][better]
    parent = np.arange(kappa.size)

    def root(c):
        while parent[c] != c:
            parent[c] = parent[parent[c]]
            c = parent[c]
        return c

    for c, target in zip(small, best):  # union of every small cell with its target
        a, b = root(c), root(target)
        parent[max(a, b)] = min(a, b)
    members = np.union1d(small, best)
    group[members] = [root(c) for c in members]
    return group


def immersed_boundary(grid, shapes, periodic=(False, False), band: float = 3.0, radial: int = 0) -> ImmersedBoundary:
    """Cut cells and ghost-cell tables for ``shapes`` on the 2D ``grid``
    (square cells); ``radial = 1``: the r–z plane of an axisymmetric run
    (x the radius), where faces and volumes are those of rings
    (:mod:`partmesh.gridref.revolution`) and the wall vector closes the cell
    against the hoop source too (module docstring of :mod:`partmesh.gridref.euler.step`)."""
    X, Y = mesh(grid)
    h = grid.step[0]
    kappa, ax, ay = cut_cells(grid, shapes, periodic)
    # −(Σ_f α_f A_f n_f)/V: the wall vector that closes each planar cell, per cell area; its direction is the wall's
    planar = np.stack([-(ax[:, 1:] - ax[:, :-1]) / h, -(ay[1:] - ay[:-1]) / h])
    cut = np.flatnonzero((kappa > 0.0) & (np.hypot(planar[0], planar[1]) > 1e-12 / h))
    wall, weight = planar, 1.0
    if radial:  # B/V = κ g e_r − (Σ_f α_f a_f A_f n_f)/V with ring faces a_f and volumes v: the hoop source closes too
        nx = kappa.shape[1]
        a, v = face_areas(0, nx + 1, h, radial), cell_volumes(0, nx, h, radial)
        wall = np.stack([kappa * hoop(0, nx, h, radial) - (ax[:, 1:] * a[1:] - ax[:, :-1] * a[:-1]) / (v * h),
                         planar[1]])
        weight = revolved(kappa.shape, h, radial)
    phi, (nx, ny) = signed_distance(shapes, X, Y), normal(shapes, X, Y)
    fluid = kappa > 0.0
    ghost = np.flatnonzero(~fluid & (phi > -band * h))
    g_phi, g_nx, g_ny = phi.ravel()[ghost], nx.ravel()[ghost], ny.ravel()[ghost]
    image = np.stack([X.ravel()[ghost] - 2.0 * g_phi * g_nx, Y.ravel()[ghost] - 2.0 * g_phi * g_ny], axis=1)
    stencil, weights = bilinear_stencil(grid, image, periodic)
    weights = weights * fluid.ravel()[stencil]
    total = weights.sum(axis=1)
    orphans = total <= 1e-12
    if np.any(orphans):
        from scipy.spatial import cKDTree

        fluid_idx = np.flatnonzero(fluid.ravel())
        tree = cKDTree(np.stack([X.ravel()[fluid_idx], Y.ravel()[fluid_idx]], axis=1))
        _, nearest = tree.query(image[orphans])
        stencil[orphans] = fluid_idx[nearest][:, None]
        weights[orphans] = 0.25
        total[orphans] = 1.0
    weights = weights / total[:, None]
    return ImmersedBoundary(
        shape=kappa.shape, volume=kappa, solid=phi < 0.0, apertures=(ax, ay), cut=cut,
        wall=np.stack([w.ravel()[cut] for w in wall]), wall_normal=_unit(np.stack([w.ravel()[cut] for w in planar])),
        ghost=ghost, stencil=stencil, weights=weights, normal=np.stack([g_nx, g_ny]),
        periodic=tuple(bool(p) for p in periodic), group=merge_groups(kappa, periodic), weight=weight,
    )


def _unit(vectors: np.ndarray) -> np.ndarray:
    """The columns of ``vectors`` (2, n) scaled to unit length."""
    return vectors / np.hypot(*vectors)
