"""Method ``fv`` on a block-structured hierarchy (``levels`` > 1, SPEC §3.8).

Level 0 covers the domain at ``dx · 2^(levels−1)``; every finer level
halves the spacing where Löhner's estimate of the level below passes the
``refine`` threshold (:mod:`partmesh.gridref.amr.sensor`), with a buffer
of blocks wide enough that a front cannot leave the finest level before
the next regrid, at the start of every few steps of level 0 (as many as
the buffer covers, at most :data:`REGRID_INTERVAL`). The step of level
0 subcycles every finer level (:mod:`partmesh.gridref.amr.subcycle`), each
level advanced by the MUSCL–Hancock step of its active blocks
(:mod:`partmesh.gridref.euler.blocks`); whole stretches of such steps run
in one compiled loop (:mod:`partmesh.gridref.device_loop`), which stops
early where a block list outgrows its capacity: the host then grows it to the
next power of two a quarter above what it needs and compiles the loop anew.

Results are written on the scene's output grid from the composite state:
every output cell from the finest level that covers it.
"""

from __future__ import annotations

import math
import time as _time

import jax
import jax.numpy as jnp
import numpy as np

from partmesh.cases.checkpoint import checkpoint_for
from partmesh.cases.checks import check_initial_state
from partmesh.cases.compiling import GRID_SIZE, compiling
from partmesh.cases.history import History, Output, RunRecord
from partmesh.cases.march import Start, Stepping, march
from partmesh.compare.regrid import to_output_grid
from partmesh.gridref.amr import blockmaps
from partmesh.gridref.amr.hierarchy import GROWTH, Hierarchy, Levels, capacity_for, with_level
from partmesh.gridref.amr.layout import Layout, coords_of, layout_for
from partmesh.gridref.amr.subcycle import Subcycler, probe_stencils
from partmesh.gridref.amr.transfer import repeated
from partmesh.gridref.device_loop import device_loop
from partmesh.gridref.euler.blocks import LevelStepper, admissible, sensed
from partmesh.gridref.euler.method import FVSettings, boundary_kinds
from partmesh.gridref.euler.cut_blocks import CutBlocks
from partmesh.gridref.euler.setup import failure_sentence, immersed_for, inflow_states, named_fields
from partmesh.gridref.euler.state import conservative, primitive
from partmesh.gridref.euler.step import FLOOR, Scheme, stable_dt
from partmesh.gridref.grid import solver_grid
from partmesh.gridref.jax_setup import configure_jax
from partmesh.gridref.revolution import GEOMETRIES


class Refined:
    """The compiled parts of one refined run: the regrid, the step of level
    0 with everything inside it, and the stable step of a hierarchy."""

    def __init__(self, scene, settings: FVSettings, forced_finest: bool = False):
        self.scene, self.gamma = scene, scene.gamma
        self.layout = lay = layout_for(scene.domain, settings.dx, settings.levels, boundary_kinds(scene),
                                       settings.block)
        self.n_vars, L = lay.dim + 2, lay.levels
        radial = GEOMETRIES[scene.geometry]
        scheme = Scheme(gamma=self.gamma, dx=lay.dx, kinds=lay.kinds, limiter=settings.limiter,
                        riemann=settings.riemann, cfl=settings.cfl, radial=radial)
        #: blocks added around the flagged ones: a front moves at most cfl cells a step on every level, and a
        #: level l takes 2^l steps between two regrids
        buffer = max(1, math.ceil(settings.cfl * (1 << (L - 1)) / lay.block))
        #: steps of level 0 between two regrids: as many as the buffer covers (the finest level's front moves at
        #: most cfl · 2^(L−1) of its cells a step of level 0), at most :data:`REGRID_INTERVAL`
        self.interval = max(1, min(REGRID_INTERVAL, int(buffer * lay.block // (settings.cfl * (1 << (L - 1))))))
        immersed = immersed_for(scene, solver_grid(scene.domain, settings.dx))
        #: the bodies' cut cells on the finest level, whose blocks that meet them are always active
        self.cut = None if immersed is None else CutBlocks(immersed, lay, L - 1)
        self.levels = Levels(lay, self.n_vars, admissible(self.gamma), sensed(self.gamma), settings.refine,
                             settings.derefine, settings.gradient, buffer, radial,
                             None if self.cut is None else self.cut.volume)
        self.stepper = LevelStepper(self.levels, scheme, self.cut)
        if forced_finest:
            self.forced = tuple(jnp.ones(lay.blocks(level)[::-1], bool) for level in range(L))
        elif self.cut is not None:  # (one block around them: their redistribution reads one cell beyond)
            bodies = blockmaps.dilated(jnp.asarray(self.cut.blocks.reshape(lay.blocks(L - 1)[::-1])), lay.periodic)
            self.forced = (None,) * (L - 1) + (bodies,)
        else:
            self.forced = None
        points = [pr.at(lay.dim) for pr in scene.probes] or [(0.0,) * lay.dim]
        self.stencils = [tuple(jnp.asarray(a) for a in s) for s in probe_stencils(self.levels, points)]
        gamma, n_vars = self.gamma, self.n_vars

        def imposed(t):
            W = inflow_states(scene, t)
            return jnp.stack(conservative(tuple(W[:, k] for k in range(n_vars)), gamma), axis=1)

        self.imposed = imposed
        self.subcycler = Subcycler(self.levels, self.stepper.step, imposed, self.probe, len(points), 2 * lay.dim)

    def probe(self, H: Hierarchy, theta):
        """The pressure at every probe from the finest level whose active
        blocks hold its stencil, level ``l`` at ``(1 − θ_l) old + θ_l U``."""
        L, value = self.layout.levels, None
        for level, (index, weights, blocks) in enumerate(self.stencils):
            at = [u.ravel()[index] for u in H.U[level]]
            if level < L - 1:
                at = [(1.0 - theta[level]) * b + theta[level] * a
                      for a, b in zip(at, (o.ravel()[index] for o in H.old[level]))]
            v = jnp.sum(primitive(tuple(at), self.gamma)[-1] * weights, axis=-1)
            value = v if value is None else jnp.where(jnp.all(H.maps[level].ravel()[blocks], axis=-1), v, value)
        return value

    def step(self, H: Hierarchy, t, dt):
        """A step of level 0 after a regrid; halts (the fifth value True, the
        state's ``need`` set, nothing else changed) where a block list is too
        short. A halted step is the step of a hierarchy with no block listed
        (every loop runs no pass, every scatter drops), not a conditional,
        whose branches would copy every level's storage in and out."""
        H, short = self.levels.regridded(H, self.imposed(t), self.forced, due=H.steps % self.interval == 0)
        lay = self.layout

        def idle(lists):
            return tuple((jnp.where(short, lay.n_blocks(level), ids), jnp.where(short, 0, count))
                         for level, (ids, count) in enumerate(lists))

        moved, dt_next, probes, forces = self.subcycler.advance(H._replace(active=idle(H.active), halo=idle(H.halo)),
                                                                t, dt)
        dt_next = jnp.where(short, dt, jnp.minimum(dt_next, H.dt_limit))
        # (an idle step adds no cell updates and no floors: only the lists and the step's limit are put back)
        H = moved._replace(active=H.active, halo=H.halo, dt_limit=jnp.where(short, H.dt_limit, GROWTH * dt_next),
                           steps=jnp.where(short, H.steps, H.steps + 1))
        return H, dt_next, probes, forces, short

    def first_dt(self, H: Hierarchy) -> float:
        """The first step of level 0: its stable step shrunk by 2^(levels−1),
        so that it lasts no longer than one stable step of the finest level
        (the uniform grid's first step), each of its 2^(levels−1) finest
        steps that much shorter: the waves an initial jump starts speed up at
        once, and the finest level's steps are fixed for the whole step of
        level 0. From there the steps grow by :data:`GROWTH` at most."""
        return float(jax.jit(self.stable_dt)(H)) / (1 << (self.layout.levels - 1))

    def stable_dt(self, H: Hierarchy):
        """The largest step of level 0 every level allows: min over l of 2ˡ
        times its CFL step (NaN if a level holds a state that is not physical)."""
        dts = []
        for level in range(self.layout.levels):
            ids, count = H.active[level]
            U = self.levels.blocks_of(H.U[level], ids)
            valid = (jnp.arange(ids.shape[0]) < count).reshape((-1,) + (1,) * self.layout.dim)
            fluid = jnp.broadcast_to(valid, U[0].shape)
            if self.cut is not None and level == self.layout.levels - 1:
                fluid = fluid & jnp.asarray(self.cut.fluid)[ids]
            dts.append(stable_dt(U, self.gamma, self.layout.spacing(level), self.stepper.schemes[level].cfl, fluid,
                                 self.stepper.crowding(level, ids)) * (1 << level))
        return jnp.min(jnp.stack(dts))

    # --- the initial hierarchy -----------------------------------------------------------------------
    def initial(self, t0: float) -> Hierarchy:
        """The scene's initial state on every level where the estimator asks
        for it: level 0, then each finer level set from the scene's initial
        state on the blocks the level below flags; finally every level's
        cells under a finer one set to the means of their children."""
        lay, L = self.layout, self.layout.levels
        full = [lay.n_blocks(level) for level in range(L)]
        H = self._empty(full, full)
        H = H._replace(U=with_level(H.U, 0, self._initial_blocks(0, np.arange(full[0]))))
        regrid = jax.jit(lambda H: self.levels.regridded(H, self.imposed(t0), self.forced, fill=False)[0])
        for _ in range(L - 1):
            H = regrid(H)
            for level in range(1, L):
                ids, count = (np.asarray(a) for a in H.active[level])
                ids = ids[:int(count)]
                H = H._replace(U=with_level(H.U, level, self.levels.with_blocks(H.U[level], jnp.asarray(ids),
                                                                        self._initial_blocks(level, ids))))
        restrict = jax.jit(self.levels.restricted_into, static_argnums=2)
        for level in range(L - 1, 0, -1):
            coarser = restrict(H.U[level - 1], H.U[level], level, *H.active[level])
            H = H._replace(U=with_level(H.U, level - 1, coarser))
        counts = np.asarray(H.need)
        # lists start with room for a tenth of a level's blocks (and a quarter more, to a power of two), a
        # small level's for all of them: a front that grows from a point would otherwise outgrow them several
        # times, each a compile of the loop; an empty slot costs little (its chunk is not advanced)
        room = [n if n <= SMALL_LEVEL else capacity_for(n // 10, n) for n in full]

        def caps(column):
            return [max(capacity_for(int(c), n), r) for c, n, r in zip(counts[1:, column], full[1:], room[1:])]

        return with_capacity(H, [full[0]] + caps(0), [1] + caps(1), lay)

    def _initial_blocks(self, level: int, ids: np.ndarray):
        """The scene's initial conservative state on the blocks ``ids`` of ``level``."""
        lay, B = self.layout, self.layout.block
        h = lay.spacing(level)
        coords = coords_of(np.asarray(ids), lay.blocks(level))
        lanes = np.arange(B) + 0.5
        if lay.dim == 1:
            X, Y = (lay.origin[0] + (coords[0][:, None] * B + lanes[None, :]) * h[0]).ravel(), None
        else:
            X = lay.origin[0] + (coords[0][:, None, None] * B + lanes[None, None, :]) * h[0]
            Y = lay.origin[1] + (coords[1][:, None, None] * B + lanes[None, :, None]) * h[1]
            X, Y = (np.broadcast_to(a, (len(ids), B, B)).reshape(-1, B) for a in (X, Y))
        rho, u, v, p = (np.broadcast_to(np.asarray(a, float), X.shape) for a in self.scene.initial(X, Y, h[0]))
        check_initial_state(self.scene, rho, p, X, Y)
        W = (rho, u, p) if lay.dim == 1 else (rho, u, v, p)
        return tuple(jnp.asarray(a.reshape((len(ids), *lay.block_shape))) for a in conservative(W, self.gamma))

    def _empty(self, caps, halo_caps) -> Hierarchy:
        lay, L, levels = self.layout, self.layout.levels, self.levels
        full = [lay.n_blocks(level) for level in range(L)]
        U = tuple(levels.empty(level) for level in range(L))
        old = tuple(levels.empty(level) for level in range(L - 1))
        flux = tuple(tuple(tuple(jnp.zeros((full[level], *lay.face_shape(d))) for _ in range(self.n_vars))
                           for d in range(lay.dim)) for level in range(L - 1))
        maps = tuple(jnp.full(lay.blocks(level)[::-1], level == 0) for level in range(L))
        active = [(jnp.arange(full[0], dtype=jnp.int32), jnp.asarray(full[0], jnp.int32))]
        active += [(jnp.full(caps[level], full[level], jnp.int32), jnp.zeros((), jnp.int32)) for level in range(1, L)]
        halo = [(jnp.zeros(1, jnp.int32), jnp.zeros((), jnp.int32))]
        halo += [(jnp.full(halo_caps[level], full[level], jnp.int32), jnp.zeros((), jnp.int32))
                 for level in range(1, L)]
        H = Hierarchy(U=U, old=old, flux=flux, register=(), active=tuple(active), halo=tuple(halo), maps=maps,
                      floors=jnp.zeros(3), updates=jnp.zeros(()), need=jnp.zeros((L, 2), jnp.int32),
                      dt_limit=jnp.asarray(jnp.inf), peak=jnp.zeros(L + 1, jnp.int32), steps=jnp.zeros((), jnp.int32))
        return with_capacity(H, caps, halo_caps, lay)


def capacities(H: Hierarchy) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """The capacities of every level's active and halo lists."""
    return tuple(a[0].shape[0] for a in H.active), tuple(h[0].shape[0] for h in H.halo)


def with_capacity(H: Hierarchy, caps, halo_caps, lay: Layout) -> Hierarchy:
    """``H`` with block lists of capacities ``caps`` and ``halo_caps`` (cut
    or padded with the id past the last block; the lists hold no more than
    that) and registers to match."""
    def resized(pair, cap, level):
        ids, count = pair
        ids = np.asarray(ids)[:cap]
        pad = np.full(cap - ids.size, lay.n_blocks(level), np.int32)
        return jnp.asarray(np.concatenate([ids, pad]).astype(np.int32)), count

    L = lay.levels
    active = tuple(resized(H.active[level], caps[level], level) for level in range(L))
    halo = tuple(resized(H.halo[level], halo_caps[level], level) for level in range(L))
    register = ((),) + tuple(tuple(tuple(jnp.zeros((caps[level], *lay.edge_shape)) for _ in range(lay.dim + 2))
                                   for _ in range(lay.dim)) for level in range(1, L))
    return H._replace(active=active, halo=halo, register=register)


#: the most steps of level 0 between two regrids (AMReX's ``regrid_int`` is 2 by default; Berger & Colella regrid
#: every few coarse steps): a feature that appears where no level is fine waits at most this long for one
REGRID_INTERVAL = 4


#: the blocks of a level small enough to be listed whole from the start (its lists never grow)
SMALL_LEVEL = 128


def grown(H: Hierarchy, lay: Layout) -> Hierarchy | None:
    """``H`` with every block list grown to :func:`capacity_for` twice what
    the last regrid asked for (``need``) where one list is too short for it
    (a front that outgrew one list is about to outgrow the others, and each
    growth is a compile of the loop); None if none is."""
    caps, halo_caps = capacities(H)
    need = np.asarray(H.need)
    if not any(int(need[level, 0]) > caps[level] or int(need[level, 1]) > halo_caps[level]
               for level in range(1, lay.levels)):
        return None
    most = [lay.n_blocks(level) for level in range(1, lay.levels)]
    caps = [caps[0]] + [max(c, capacity_for(2 * int(n), m)) for c, n, m in zip(caps[1:], need[1:, 0], most)]
    halo_caps = [halo_caps[0]] + [max(c, capacity_for(2 * int(n), m))
                                  for c, n, m in zip(halo_caps[1:], need[1:, 1], most)]
    return with_capacity(H, caps, halo_caps, lay)


def composite(H: Hierarchy, lay: Layout) -> list[np.ndarray]:
    """The conservative state on the finest grid (field layout ``([y,] x)``):
    every cell from the finest level whose active blocks cover it (coarser
    levels' cells repeated)."""
    out = None
    for level in range(lay.levels):
        fields = [_global(np.asarray(u), lay, level) for u in H.U[level]]
        if out is None:
            out = fields
            continue
        out = [repeated(a, 2) for a in out]
        covered = repeated(np.asarray(H.maps[level]), lay.block)
        for a, f in zip(out, fields):
            a[covered] = f[covered]
    return out


def _global(u: np.ndarray, lay: Layout, level: int) -> np.ndarray:
    """A level's block-major array as one array over the level's cells."""
    if lay.dim == 1:
        return u.reshape(-1).copy()
    nbx, nby = lay.blocks(level)
    B = lay.block
    return u.reshape(nby, nbx, B, B).transpose(0, 2, 1, 3).reshape(nby * B, nbx * B)


class GrowingLoop:
    """The stretch of a refined run: the compiled loop of the step of level
    0 for the hierarchy's present capacities; where a stretch stops because
    a block list is too short, the lists grow (:func:`grown`) and the next
    stretch compiles the loop for them (its compile time reported apart)."""

    n_records = 256

    def __init__(self, refined: Refined, n_probes: int, n_forces: int, on_compile):
        self.refined, self.n_probes, self.n_forces, self.on_compile = refined, n_probes, n_forces, on_compile
        self._loops = {}

    def loop(self, H: Hierarchy):
        key = capacities(H)
        if key not in self._loops:
            started = _time.perf_counter()
            loop = device_loop(self.refined.step, self.n_probes, self.n_forces, self.n_records,
                               per_step=self.refined.subcycler.records, halts=True)
            loop.compile(H)
            self._loops[key] = loop
            self.on_compile(_time.perf_counter() - started)
        return self._loops[key]

    def __call__(self, H, t, dt_cfl, t_out, n_max, dt_floor):
        s = self.loop(H)(H, t, dt_cfl, t_out, n_max, dt_floor)
        larger = grown(s.state, self.refined.layout)
        if larger is not None:
            s.state = larger
            self.loop(larger)
        return s


def solve_refined(scene, settings: FVSettings, forced_finest: bool = False):
    """Run ``scene`` with ``fv`` on ``settings.levels`` levels (see the module
    docstring); ``forced_finest``: every block of every level active (the
    hierarchy then steps its finest level as the uniform grid of ``dx``
    would, given the same steps)."""
    configure_jax()
    return run_refined(scene, settings, Refined(scene, settings, forced_finest))


def run_refined(scene, settings: FVSettings, refined: Refined):
    """Run ``scene`` with the compiled parts of a refined run, ``refined``."""
    lay = refined.layout
    started = _time.perf_counter()
    H = refined.initial(scene.t_start)
    n_probes = refined.subcycler.n_probes
    dt_cfl = refined.first_dt(H)
    H = H._replace(dt_limit=jnp.asarray(GROWTH * dt_cfl))
    probes0 = np.asarray(refined.probe(H, jnp.ones(lay.levels)))
    run = _RefinedRun(scene, refined, settings.record(), 0.0, History(probes0, 2 * lay.dim, scene.t_start))

    def compiled(seconds):
        run.compile_seconds += seconds
        run.t_start += seconds  # (compile time is reported apart from the run's)

    advance = GrowingLoop(refined, n_probes, 2 * lay.dim, compiled)
    with compiling("fv", settings.progress, GRID_SIZE):
        advance.loop(H)
    run.compile_seconds += _time.perf_counter() - started - run.compile_seconds
    run.t_start = _time.perf_counter()
    t = scene.t_start
    ckpt = checkpoint_for(scene, settings)
    saved = ckpt.saved_state(run)
    if saved is not None:
        H = jax.tree_util.tree_map(jnp.asarray, saved["state"])
        t, dt_cfl = saved["t"], saved["dt_cfl"]

    def diagnose(H, t, step, dt, failed):
        if failed:  # the state the failed step of dt made
            H = jax.jit(refined.step)(H, t, dt)[0]
            t = t + dt
        U = tuple(jnp.asarray(a) for a in composite(H, lay))
        return failure_sentence(U, refined.gamma, solver_grid(scene.domain, settings.dx), t, step, dt)

    def saved_state(H, t, dt_cfl):
        return {"state": jax.tree_util.tree_map(np.asarray, H), "t": t, "dt_cfl": dt_cfl}

    return march(run, Start(H, t, dt_cfl), Stepping(advance, saved_state, diagnose), ckpt, settings)


class _RefinedRun(RunRecord):
    """The record of one refined fv run: frames go to the output grid as
    they are taken (the composite state lives on the finest grid)."""

    def __init__(self, scene, refined: Refined, settings, compile_seconds, history):
        super().__init__(scene, "fv", settings, compile_seconds, history)
        self.refined, self.layout = refined, refined.layout
        self.how = ""

    def fields(self, H):
        lay, scene = self.layout, self.scene
        values = named_fields(primitive(tuple(composite(H, lay)), scene.gamma), scene.gamma, scene.fields)
        centres = lay.cell_centres(lay.levels - 1)
        out = scene.output
        pairs = (centres[0], out.x) if lay.dim == 1 else (centres[0], out.x, centres[1], out.y)
        fields = {}
        for name in scene.fields:
            fields[name], self.how = to_output_grid(values[name][None], *pairs, periodic=scene.periodic + (False,))
            fields[name] = fields[name][0]
        return fields

    def totals(self, H) -> dict:
        """Mass and energy of the hierarchy (of revolution, the whole
        revolved body): level 0 holds the means of every finer level over
        the cells they cover."""
        volume = np.asarray(self.refined.stepper.volumes(0, jnp.arange(self.layout.n_blocks(0))))
        if self.refined.levels.open_fractions is not None:  # the gas's part of each cell
            volume = volume * self.refined.levels.open_fractions[0]
        if volume.ndim == 0:  # planar: every cell alike
            return {name: float(np.sum(np.asarray(H.U[0][i]))) * float(volume)
                    for name, i in (("mass", 0), ("energy", -1))}
        return {name: float(np.sum(np.asarray(H.U[0][i]) * volume)) for name, i in (("mass", 0), ("energy", -1))}

    def output(self) -> Output:
        lay, s = self.layout, self.settings
        fields = {name: self.stacked(name) for name in self.scene.fields}
        scheme = (f"unsplit MUSCL-Hancock, {s['limiter']} limiter on primitive variables, {s['riemann'].upper()} flux, "
                  f"on {lay.levels} levels of ratio 2 (blocks of {lay.block} cells, Berger-Colella subcycling and "
                  f"refluxing, MC-limited conservative prolongation, Lohner estimator on density and pressure: refine "
                  f"above {s['refine']:g}, keep above {s['derefine']:g}; relative variation above {s['gradient']:g}), "
                  "a-posteriori positivity fallback to first "
                  f"order, vacuum floors ({FLOOR:g} of the largest density and pressure) where a near-vacuum still "
                  "turns negative")
        H = self.state
        cells, mass, energy = np.asarray(H.floors)
        blocks = int(np.asarray(H.peak)[-1])
        cells_max = blocks * lay.block ** lay.dim
        attrs = {"regrid": f"finest-level composite, {self.how}", "levels": lay.levels, "block": lay.block,
                 "blocks_max": blocks, "cells_max": cells_max, "cell_updates": float(H.updates),
                 "vacuum_floors": int(cells), "vacuum_floor_mass": float(mass), "vacuum_floor_energy": float(energy)}
        return Output(fields, None, scheme, cells_max, attrs)
