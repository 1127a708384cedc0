"""The vertical slice (x, z) a water scene becomes for the water SPH: its
walls, its water at rest and its damping zone
(SPEC §3.2, §4.3).

A planar water scene is 1D in x; its slice has the bed ``z_b(x)`` below
and the free surface above. The sides of the slice, in the order of a 2D
scene (``x_lo``, ``x_hi``, ``y_lo``, ``y_hi``; y is the height z): the
scene's x sides (``reflect``: a wall; ``absorbing``: a damping zone before
a wall; ``outflow``: zero gradient; ``periodic``), the bed (``reflect``)
and the surface (``free``: no ghosts).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from partmesh.cases.errors import InputError, Unsupported
from partmesh.particle.wcsph.eos import Tait


@dataclass(frozen=True)
class Flume:
    """The slice of a planar water ``scene``: ``sides``, ``boundaries`` and
    ``domain`` (x, then z from the bed to ``top``) as
    :func:`partmesh.particle.sph.particles.mirror_ghosts` reads them; ``bed`` is the
    flat bed's elevation, ``damping`` the length of the damping zone before
    an absorbing x_hi (0 if none)."""

    sides: tuple
    boundaries: dict
    domain: tuple
    bed: float
    damping: float

    @property
    def periodic(self) -> np.ndarray:
        return np.array([self.boundaries["x_lo"] == "periodic", False])

    def without_bed(self) -> "Flume":
        """The same flume with no ghosts below the bed (the x walls only)."""
        return dataclasses.replace(self, boundaries={**self.boundaries, "y_lo": "free"})


def flume(scene, dx: float, damping: float | None) -> Flume:
    """The slice of ``scene``, or a one-sentence refusal of what the water
    SPH does not model: plan-view (2D) and radial scenes, beds that are not
    flat. ``damping`` is the damping-zone length before an absorbing x_hi
    (None: a fifth of the flume)."""
    if scene.dim != 1 or scene.geometry != "planar":
        raise Unsupported(f"scene {scene.name}: wcsph runs planar 1D water scenes as a vertical (x, z) slice, "
                          f"not {'radial' if scene.geometry == 'radial' else f'{scene.dim}D plan-view'} ones.")
    (x0, x1), = scene.domain
    xs = np.linspace(x0, x1, 257)
    bed = np.broadcast_to(np.asarray(scene.bed(xs, None), float), xs.shape)
    if np.ptp(bed) > 1e-9 * scene.depth:
        raise Unsupported(f"scene {scene.name}: wcsph takes flat beds only (this bed spans "
                          f"{bed.min():g} to {bed.max():g} m).")
    kinds = {side: scene.boundaries[side] for side in ("x_lo", "x_hi")}
    if kinds["x_lo"] == "absorbing":
        raise Unsupported(f"scene {scene.name}: wcsph has its damping zone at x_hi only, not x_lo.")
    if kinds["x_hi"] == "absorbing":
        damping = 0.2 * (x1 - x0) if damping is None else damping
        if not 0.0 < damping < 0.5 * (x1 - x0):
            raise InputError(f"damping must be in (0, {0.5 * (x1 - x0):g}) m (half the flume), got {damping:g} m.")
        reach = max([pr.x for pr in scene.probes], default=x0)
        if x1 - damping <= reach:
            raise InputError(f"damping = {damping:g} m reaches over the gauge at x = {reach:g} m: use "
                             f"damping < {x1 - reach:g} m.")
    else:
        damping = 0.0
    # the water's top: the highest initial surface, and room for the waves above it
    eta0 = np.broadcast_to(np.asarray(scene.initial(xs, None)[0], float), xs.shape)
    top = float(bed[0]) + 3.0 * float(np.max(eta0 - bed[0])) + 10.0 * dx
    boundaries = {"x_lo": kinds["x_lo"], "x_hi": "reflect" if kinds["x_hi"] == "absorbing" else kinds["x_hi"],
                  "y_lo": "reflect", "y_hi": "free"}
    return Flume(("x_lo", "x_hi", "y_lo", "y_hi"), boundaries, ((x0, x1), (float(bed[0]), top)), float(bed[0]),
                 damping)


def water_at_rest(scene, flume: Flume, dx: float, eos: Tait):
    """Particles of the scene's initial water: ``(x, v, rho, m)``.

    Columns ``dx`` wide; the column at x holds N = round(h0/dx) particles
    spaced h0/N apart (h0 = η0(x) − z_b), so its volume is the initial
    water's exactly; each particle carries the hydrostatic pressure of its
    column (:meth:`Tait.hydrostatic_pressure`) through the density of the
    equation of state,
    and the mass ρ V of its cell V = dx · h0/N."""
    (x0, x1), _ = flume.domain
    nx = int(round((x1 - x0) / dx))
    xc = x0 + (np.arange(nx) + 0.5) * (x1 - x0) / nx
    eta0, u0, _ = (np.broadcast_to(np.asarray(a, float), xc.shape) for a in scene.initial(xc, None))
    h0 = np.maximum(eta0 - flume.bed, 0.0)
    rows = np.rint(h0 / dx).astype(np.int64)
    if rows.max() < 4:
        raise InputError(f"dx = {dx:g} m leaves fewer than 4 particles over the depth (deepest water "
                         f"{h0.max():g} m): use dx <= {h0.max() / 4:.4g} m.")
    column = np.repeat(np.arange(nx), rows)
    k = np.arange(column.size) - np.repeat(np.cumsum(rows) - rows, rows)
    dz = h0[column] / rows[column]
    z = flume.bed + (k + 0.5) * dz
    x = np.stack([xc[column], z], axis=1)
    rho = eos.density(eos.hydrostatic_pressure(eta0[column] - z, scene.g))
    v = np.stack([u0[column], np.zeros(column.size)], axis=1)
    return x, v, rho, rho * (x1 - x0) / nx * dz


def damping_rate(flume: Flume, x, g: float, depth: float):
    """The relaxation rate σ(x) [s⁻¹] of the velocity in the damping zone
    (v ← v/(1 + Δt σ) every step): σ = σ_max ξ², ξ the fraction of the zone
    crossed, σ_max = 10 sqrt(g/d) (ten long-wave periods of a depth)."""
    if flume.damping == 0.0:
        return np.zeros(x.shape[0])
    start = flume.domain[0][1] - flume.damping
    xi = np.clip((x[:, 0] - start) / flume.damping, 0.0, 1.0)
    return 10.0 * np.sqrt(g / depth) * xi * xi
