"""Initial particle placement and boundary (ghost) particles for gas SPH.

Particles have equal mass ``m = ρ_max Δx^d``: ``Δx`` is the spacing in the
densest initial gas and lighter gas gets proportionally wider spacing.
"""

from __future__ import annotations

import numpy as np

from partmesh.cases.ball import ring_volumes
from partmesh.cases.errors import InputError, Unsupported
from partmesh.cases.scene import Inflow
from partmesh.particle.sph.wall_placement import off_surface


def initial_state(scene, x, dx: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The scene's initial ``(rho, v, p)`` at the points ``x`` (n, dim), ``v``
    (n, dim): ``scene.initial`` called as its dimension asks (SPEC §4)."""
    coords = [x[:, a] for a in range(scene.dim)]
    given = scene.initial(coords[0], coords[1] if scene.dim > 1 else None, dx, *coords[2:])
    rho, *velocity, p = (np.broadcast_to(np.asarray(a, float), x[:, 0].shape).copy() for a in given)
    return rho, np.stack(velocity[: scene.dim], axis=1), p


def _side_state(scene, side: str, dx: float):
    """Initial ``(c, u_n)`` at points over ``side``: sound speed and the
    velocity along the side's outward normal."""
    d = scene.sides.index(side)
    axis, upper = d // 2, d % 2 == 1
    along = [np.linspace(*extent, 65) if a != axis else np.array([extent[1 if upper else 0]])
             for a, extent in enumerate(scene.domain)]
    x = np.stack([c.ravel() for c in np.meshgrid(*along, indexing="ij")], axis=1)
    rho, v, p = initial_state(scene, x, dx)
    return np.sqrt(scene.gamma * p / rho), v[:, axis] * (1.0 if upper else -1.0)


def outflow_reach(scene, dx: float, t_end: float, margin: float) -> dict[str, float]:
    """How far the particle set extends beyond each ``outflow`` side.

    Where the initial flow runs along the side or is at rest there (a free
    stream past the top of the wedge tunnel, the quiet ends of a shock
    tube), nothing: zero-gradient ghosts stand beyond it
    (:func:`mirror_ghosts`). Elsewhere the free end of the particle set
    must stay out of reach of the domain: the set extends by the distance
    a signal from it covers upstream in the run, ``1.5 max(c − u_n, 0) t``
    (``u_n`` the outward normal velocity: nothing comes back through
    supersonic outflow; gas flowing in, as in Noh's problem, brings its
    free end closer at ``c + |u_n|``), plus ``margin``, capped at twice the
    domain's length along that axis. Particles beyond the extended set are
    removed (:func:`partmesh.particle.sph.wall_placement.in_box`)."""
    reach = {}
    for d, side in enumerate(scene.sides):
        if scene.boundaries[side] != "outflow":
            continue
        c, u_n = _side_state(scene, side, dx)
        if np.all(np.abs(u_n) <= 1e-12 * c):
            reach[side] = 0.0
        else:
            length = np.subtract(*scene.domain[d // 2][::-1])
            reach[side] = min(1.5 * float(np.max(np.maximum(c - u_n, 0.0))) * t_end + margin, 2.0 * length)
    return reach


def extended_domain(scene, reach: dict[str, float]) -> list[tuple[float, float]]:
    """The region filled with fluid particles: the scene's domain extended
    beyond each side by ``reach[side]`` (0 for sides not in it)."""
    return [(lo - reach.get(scene.sides[2 * d], 0.0), hi + reach.get(scene.sides[2 * d + 1], 0.0))
            for d, (lo, hi) in enumerate(scene.domain)]


def place_1d(scene, dx: float, box) -> tuple[np.ndarray, float]:
    """Equal-mass positions along x over ``box`` for the scene's initial
    density: particle k sits where the cumulative mass reaches (k + ½) m,
    so each particle carries exactly the mass of its share of the profile."""
    lo, hi = box[0]
    fine = np.linspace(lo, hi, int(np.ceil((hi - lo) / dx)) * 64 + 1)
    rho = np.broadcast_to(np.asarray(scene.initial(fine, None, dx)[0], float), fine.shape)
    mass = np.concatenate([[0.0], np.cumsum(0.5 * (rho[1:] + rho[:-1]) * np.diff(fine))])
    m = rho.max() * dx
    n = int(np.floor(mass[-1] / m))
    targets = (np.arange(n) + 0.5) * mass[-1] / n
    return np.interp(targets, mass, fine)[:, None], mass[-1] / n


#: the largest initial density ratio the 2D row placement takes (its particles are
#: ρ_max/ρ times wider apart along x than along y in the lighter gas)
MAX_ROW_DENSITY_RATIO = 2.0


def place_2d(scene, dx: float, box) -> tuple[np.ndarray, float]:
    """Equal-mass particles over ``box`` outside the obstacles (``φ > 0``),
    points closer than ``dx/2`` to a surface moved off it to ``dx/2``
    (:func:`partmesh.particle.sph.wall_placement.off_surface`).

    A uniform initial density gets the square lattice of spacing ``dx``
    (the lattice points inside the obstacles are the walls' virtual
    particles). A non-uniform one (up to a ratio
    :data:`MAX_ROW_DENSITY_RATIO`) gets rows ``dx`` apart along which the
    mass is inverted as in :func:`place_1d`: the rows laid end to end, the
    particle k sits where the cumulative mass reaches (k + ½) m, so every
    particle carries the same mass and each row's share of the profile."""
    (x0, x1), (y0, y1) = box
    nx, ny = int(round((x1 - x0) / dx)), int(round((y1 - y0) / dx))
    X, Y = np.meshgrid(x0 + (np.arange(nx) + 0.5) * (x1 - x0) / nx, y0 + (np.arange(ny) + 0.5) * (y1 - y0) / ny)
    x = np.stack([X.ravel(), Y.ravel()], axis=1)
    rho = np.broadcast_to(np.asarray(scene.initial(x[:, 0], x[:, 1], dx)[0], float), x[:, 0].shape)
    mass = rho.max() * (x1 - x0) * (y1 - y0) / (nx * ny)
    if np.ptp(rho) > 1e-12 * rho.max():
        x, mass = _rows(scene, dx, box, ny)
    for shape in scene.obstacles:
        x = x[shape.signed_distance(x[:, 0], x[:, 1]) > 0.0]
    return off_surface(scene.obstacles, x, 0.5 * dx), mass


def place_lattice(scene, dx: float, box) -> tuple[np.ndarray, np.ndarray]:
    """Particles on the square (cubic) lattice of spacing ``dx`` over ``box`` (outside
    the obstacles, moved off their surfaces as in :func:`place_2d`), each of
    mass ρ dx^d with the scene's initial density at its point (the density
    of the cell of side ``dx`` about it): unequal masses where the density
    varies, for contrasts the equal-mass placements do not take. In an
    axisymmetric scene the masses are those of the ring cells, ρ 2π r dx²
    (:func:`partmesh.cases.ball.ring_volumes`)."""
    axes = [lo + (np.arange(int(round((hi - lo) / dx))) + 0.5) * dx for lo, hi in box]
    x = np.stack([a.ravel() for a in np.meshgrid(*axes)], axis=1)
    for shape in scene.obstacles:
        x = x[shape.signed_distance(x[:, 0], x[:, 1]) > 0.0]
    if scene.dim == 2:
        x = off_surface(scene.obstacles, x, 0.5 * dx)
    return x, initial_state(scene, x, dx)[0] * lattice_volumes(scene, x, dx)


def lattice_volumes(scene, x, dx: float):
    """The volume of the lattice cell about each point ``x``: dx^d, or the ring cell's 2π r dx² in an
    axisymmetric scene (:func:`partmesh.cases.ball.ring_volumes`)."""
    return ring_volumes(x[:, 0], dx) if scene.geometry == "axisymmetric" else dx ** scene.dim


def _rows(scene, dx: float, box, ny: int) -> tuple[np.ndarray, float]:
    """Equal-mass particles on ``ny`` rows over ``box`` by mass inversion
    along the rows laid end to end (see :func:`place_2d`)."""
    (x0, x1), (y0, y1) = box
    dy = (y1 - y0) / ny
    fine = np.linspace(x0, x1, int(np.ceil((x1 - x0) / dx)) * 64 + 1)
    rows = y0 + (np.arange(ny) + 0.5) * dy
    F, R = np.meshgrid(fine, rows)
    rho = np.broadcast_to(np.asarray(scene.initial(F.ravel(), R.ravel(), dx)[0], float), F.size).reshape(F.shape)
    if rho.max() > MAX_ROW_DENSITY_RATIO * rho.min():
        raise InputError(f"scene {scene.name}: sph in 2D places a non-uniform initial density only up to a ratio "
                         f"{MAX_ROW_DENSITY_RATIO:g} (found {rho.min():g} to {rho.max():g} kg m-3).")
    within = np.concatenate([np.zeros((ny, 1)), np.cumsum(0.5 * (rho[:, 1:] + rho[:, :-1]) * np.diff(fine) * dy,
                                                          axis=1)], axis=1)
    before = np.concatenate([[0.0], np.cumsum(within[:, -1])])
    n = int(round(before[-1] / (rho.max() * dx * dy)))
    targets = (np.arange(n) + 0.5) * before[-1] / n
    row = np.searchsorted(before, targets, side="right") - 1
    x = np.empty((n, 2))
    for j in range(ny):
        mine = row == j
        x[mine, 0] = np.interp(targets[mine] - before[j], within[j], fine)
        x[mine, 1] = rows[j]
    return x, before[-1] / n


def _mirror_sides(scene, open_):
    """``(bit, axis, upper, wall position, velocity sign)`` of every side
    ghosts are mirrored across, in the order they are applied: reflecting
    sides (normal velocity reversed) and the open sides of ``open_`` (kept)."""
    sides = []
    for d, side in enumerate(scene.sides):
        reflect = scene.boundaries[side] == "reflect"
        if reflect or side in open_:
            axis, upper = d // 2, d % 2
            sides.append((d, axis, upper, scene.domain[axis][upper], -1.0 if reflect else 1.0))
    return sides


def mirror_ghosts(scene, x, v, reach, open_: tuple[str, ...] = ()):
    """Mirror particles across every reflecting side and every side of
    ``open_`` (outflow sides the flow runs along), for the particles within
    ``reach`` of the side: ``(gx, gv, src, sides)``, the ghosts' positions
    and velocities (normal component reversed at a reflecting wall, kept at
    an open side: zero gradient, as in the finite-volume outflow), the index
    of each ghost's source particle and the bit mask of the sides it is
    mirrored across. Sides are mirrored in turn, so a corner between two
    such sides gets the double mirror image; :func:`mirror_images` makes the
    same ghosts again from moved sources.

    ``reach`` is the neighbour-search radius, one or one per particle (the
    largest sets which particles are mirrored). Between two mirrored sides
    of an axis of width W the images of upper images across the lower side
    are not made: the image of particle s there lies W + d_hi(s) + d_lo(k)
    from particle k (d: the distance to a side), so a pair that reaches
    more than W beyond both particles' distances to their sides raises
    ``FloatingPointError``, naming the particle."""
    mirrored = _mirror_sides(scene, open_)
    reach = np.broadcast_to(np.asarray(reach, float), x.shape[:1])
    for axis in sorted({a for _, a, _, _, _ in mirrored}):
        (lo, hi) = scene.domain[axis]
        if sum(a == axis for _, a, _, _, _ in mirrored) == 2 and x.shape[0]:
            d_lo, d_hi = x[:, axis] - lo, hi - x[:, axis]
            for beyond, other in ((reach - d_lo, d_hi), (reach - d_hi, d_lo)):
                k = int(np.argmax(beyond))
                if beyond[k] > (hi - lo) + float(other.min()):
                    raise FloatingPointError(f"the neighbour-search radius {reach[k]:.3g} m of the particle at x = "
                                             f"{x[k].round(6).tolist()} m reaches past the mirror images of the "
                                             f"{hi - lo:g} m between the walls across {'xyz'[axis]}: run a wider "
                                             "box or a finer dx")
    reach = float(reach.max()) if x.shape[0] else 0.0
    src, mask, gx = np.arange(x.shape[0]), np.zeros(x.shape[0], dtype=np.int64), x
    for bit, axis, upper, wall, _ in mirrored:
        near = (gx[:, axis] > wall - reach) if upper else (gx[:, axis] < wall + reach)
        mx = gx[near].copy()
        mx[:, axis] = 2.0 * wall - mx[:, axis]
        src, mask, gx = (np.concatenate([src, src[near]]), np.concatenate([mask, mask[near] | (1 << bit)]),
                         np.concatenate([gx, mx]))
    n = x.shape[0]
    return (*mirror_images(scene, x, v, src[n:], mask[n:], open_), src[n:], mask[n:])


def mirror_images(scene, x, v, src, sides, open_: tuple[str, ...] = ()):
    """``(gx, gv)``: the ghosts of :func:`mirror_ghosts` with sources ``src``
    and side masks ``sides``, made from the sources' positions ``x`` and
    velocities ``v``."""
    gx, gv = x[src], v[src]
    for bit, axis, _, wall, sign in _mirror_sides(scene, open_):
        across = (sides & (1 << bit)) != 0
        gx[across, axis] = 2.0 * wall - gx[across, axis]
        gv[across, axis] *= sign
    return gx, gv


def reflect_at_plane_walls(scene, x, *velocities):
    """The safeguard of the mirror walls: a particle that crossed a
    reflecting side is put back at its mirror image and the normal
    component of each of its ``velocities`` reversed if it points out.
    Returns ``(x, *velocities, count)`` (new arrays where any moved)."""
    crossed = np.zeros(x.shape[0], dtype=bool)
    out = [x, *velocities]
    for d, side in enumerate(scene.sides):
        if scene.boundaries[side] != "reflect":
            continue
        axis, upper = d // 2, d % 2 == 1
        wall = scene.domain[axis][1 if upper else 0]
        beyond = (out[0][:, axis] > wall) if upper else (out[0][:, axis] < wall)
        if not beyond.any():
            continue
        out = [a.copy() for a in out]
        out[0][beyond, axis] = 2.0 * wall - out[0][beyond, axis]
        for v in out[1:]:
            outward = beyond & ((v[:, axis] > 0.0) if upper else (v[:, axis] < 0.0))
            v[outward, axis] = -v[outward, axis]
        crossed |= beyond
    return (*out, int(crossed.sum()))


def check_supported(scene):
    """Refuse, in one sentence, what this SPH solver does not model yet."""
    for side in scene.sides:
        if isinstance(scene.boundaries[side], Inflow) and side != "x_lo":
            raise Unsupported(f"scene {scene.name}: sph has inflow buffers on side x_lo only, not {side}.")
    if scene.detonation is not None and scene.dim == 3:
        raise Unsupported(f"scene {scene.name}: sph carries detonation products in 1D, 2D and r-z scenes, not 3D.")
    if scene.detonation is not None and scene.obstacles:
        raise Unsupported(f"scene {scene.name}: sph carries detonation products in scenes without obstacles only "
                          "(the obstacles' virtual particles hold air).")
