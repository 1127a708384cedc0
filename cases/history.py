"""What a run records, and how it becomes a result.

Every solver, whatever its method, records after each step the pressure (or,
in water, the surface elevation) at the scene's probes and the force the gas
exerts on each side of the domain; :class:`History` turns those records into
the schema's ``p_probe`` (``eta_probe``), ``wall_force`` and
``wall_impulse`` on the scene's ``t_probe``.
:class:`RunRecord` keeps the output frames and the cost and assembles the
schema Dataset, complete or partial (``status = "failed"``).
"""

from __future__ import annotations

import time as _time
from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np
import xarray as xr
from tqdm.auto import tqdm

from partmesh.cases.errors import SolverFailed
from partmesh.compare.schema import result, source_revision


@dataclass
class History:
    """The records of one run, one per step or per probe sample.

    The history begins at ``t0`` (the scene's ``t_start``) with the probe
    values ``probes0``. A record of ``[t0, t1]`` holds the probe values at
    ``t1`` and the time-centred force on every side over the interval
    (planar: per metre depth in 2D, per square metre in 1D; of revolution:
    over the whole revolved side); the impulse is accumulated as Σ force·dt.
    """

    probes0: np.ndarray
    n_sides: int
    t0: float = 0.0
    t: list = field(default_factory=list)
    probes: list = field(default_factory=list)
    force_t: list = field(default_factory=list)
    forces: list = field(default_factory=list)
    impulses: list = field(default_factory=list)

    def __post_init__(self):
        self.t = [self.t0]
        self.probes = [np.asarray(self.probes0, float)]
        self.impulses = [np.zeros(self.n_sides)]

    def record_steps(self, t0: float, times, probes, side_forces) -> None:
        """Records of consecutive intervals from ``t0``, ending at ``times``
        (one row of ``probes`` and ``side_forces`` per interval)."""
        times = np.asarray(times, float)
        if not times.size:
            return
        starts = np.concatenate([[t0], times[:-1]])
        forces = np.asarray(side_forces, float)
        self.force_t.extend(0.5 * (starts + times))
        self.forces.extend(forces)
        # accumulated in interval order: the same impulse, to the last bit, as one record at a time
        steps = np.concatenate([self.impulses[-1][None], (times - starts)[:, None] * forces])
        self.impulses.extend(np.cumsum(steps, axis=0)[1:])
        self.t.extend(times)
        self.probes.extend(np.asarray(probes, float))

    def series(self, scene, t_probe: np.ndarray) -> dict:
        """The schema's time series of ``scene`` on ``t_probe``: ``p_probe``
        or ``eta_probe`` (the scene's ``probe_variable``, if it has probes) and ``wall_force``/``wall_impulse`` (if it
        has a target wall), the force relative to the ambient ``p0``."""
        out = {}
        if scene.probes:
            samples = np.stack(self.probes)
            out[scene.probe_variable] = np.stack([np.interp(t_probe, self.t, s) for s in samples.T], axis=1)
        if scene.wall is not None and self.forces:
            side = scene.sides.index(scene.wall.side)
            if scene.dim == 1:
                scale, ambient = scene.wall.height, scene.wall.p0
            else:
                scale, ambient = 1.0, scene.wall.p0 * scene.side_area(scene.wall.side)
            force = (np.stack(self.forces)[:, side] - ambient) * scale
            impulse = (np.stack(self.impulses)[:, side] - ambient * (np.asarray(self.t) - self.t0)) * scale
            out["wall_force"] = np.interp(t_probe, self.force_t, force)
            out["wall_impulse"] = np.interp(t_probe, self.t, impulse)
        return out


#: the wall load of an axisymmetric scene, over the wall's whole ring: (name, units, long name)
RING_LOADS = (("wall_force", "N", "force on the target wall over its whole ring, integral of (p_wall - p0) dA"),
              ("wall_impulse", "N s", "wall impulse over the whole ring, time integral of wall_force"))


@dataclass(frozen=True)
class Output:
    """What a run's record hands its Dataset (:meth:`RunRecord.output`):
    the ``fields`` on the output grid (name -> values over time and the
    grid), the output grid's ``solid`` mask (None: no body), the ``scheme``
    in words, the ``n_elements`` (cells or particles) and the method's own
    ``attrs``."""

    fields: dict
    solid: np.ndarray | None
    scheme: str
    n_elements: int
    attrs: dict = field(default_factory=dict)


class RunRecord(ABC):
    """What every solver keeps of a run: the output frames, the step
    history, the step count and the cost; and how it becomes a schema
    Dataset, complete or partial."""

    def __init__(self, scene, method: str, settings: dict, compile_seconds: float, history: History):
        self.scene, self.method, self.settings = scene, method, settings
        self.compile_seconds, self.history = compile_seconds, history
        self.frames, self.frame_times, self.frame_seconds, self.n_steps = [], [], [], 0
        source_revision()  # (the revision of the code this run loaded, read now, before the tree can change)
        self.t_start = _time.perf_counter()
        #: the last good state of the run and its time (:func:`partmesh.cases.march.march` keeps them)
        self.state, self.t = None, 0.0
        #: the conserved totals of the initial state (:meth:`totals`)
        self.totals0 = None

    def progress_bar(self, t: float, t_end: float, progress: bool):
        """The run's progress bar from ``t`` to ``t_end``: simulated time, wall
        time and its estimate to the end, and the step count the solver
        posts (``set_postfix_str``); none when ``progress`` is False or the
        output is not a terminal."""
        return tqdm(total=t_end, initial=t, disable=None if progress else True, desc=f"{self.method} {self.scene.name}",
                    leave=False, bar_format="{desc}: {percentage:3.0f}%|{bar}| t = {n:.4g}/{total:.4g} s "
                                            "[{elapsed}<{remaining}] {postfix}")

    def totals(self, state) -> dict | None:
        """The conserved totals of ``state`` (``{"mass": …, "energy": …}``),
        whose drift from the initial state a run in a closed domain reports;
        None where a method reports none."""
        return None

    def closed(self) -> bool:
        """Whether the totals should hold: no gas or water crosses a side
        (every side a wall or periodic)."""
        return all(self.scene.boundaries[side] in ("reflect", "periodic") for side in self.scene.sides)

    def drift(self) -> dict:
        """``mass_drift`` and ``energy_drift`` (relative, of the last good
        state against the initial one) where the domain is :meth:`closed`
        and the method keeps totals."""
        if not self.closed() or self.totals0 is None or self.state is None:
            return {}
        now = self.totals(self.state)
        return {f"{name}_drift": abs(now[name] - before) / abs(before) for name, before in self.totals0.items()}

    def output_frame(self, state) -> dict:
        """The fields an output frame keeps of ``state``: :meth:`fields`,
        unless a method averages its frames over steps."""
        return self.fields(state)

    @abstractmethod
    def fields(self, state) -> dict:
        """The fields (name -> array on the output grid) of ``state``."""

    def add_frame(self, fields: dict, t: float) -> None:
        """Keep the fields (name -> array) of output time ``t``, and the wall
        time the run had taken to reach it."""
        self.frames.append(fields)
        self.frame_times.append(t)
        self.frame_seconds.append(_time.perf_counter() - self.t_start)

    def stacked(self, name: str) -> np.ndarray:
        """The field ``name`` of every frame kept, stacked along time."""
        return np.stack([f[name] for f in self.frames])

    def saved(self) -> dict:
        """What a checkpoint keeps of the record (frames, history, steps,
        wall time so far)."""
        return {"frames": self.frames, "frame_times": self.frame_times, "frame_seconds": self.frame_seconds,
                "n_steps": self.n_steps, "totals0": self.totals0,
                "history": self.history, "wall": _time.perf_counter() - self.t_start}

    def restore(self, saved: dict) -> None:
        """Continue the record :meth:`saved` returned (its wall time counts)."""
        self.frames, self.frame_times = saved["frames"], saved["frame_times"]
        self.frame_seconds = saved.get("frame_seconds", [np.nan] * len(self.frame_times))
        self.n_steps, self.history, self.totals0 = saved["n_steps"], saved["history"], saved["totals0"]
        self.t_start = _time.perf_counter() - saved["wall"]

    def failure(self, message: str, t: float, frame) -> SolverFailed:
        """A :class:`SolverFailed` carrying the result up to time ``t``;
        ``frame()`` gives the fields at ``t`` if no output frame holds them."""
        if not self.frame_times or t > self.frame_times[-1]:
            self.add_frame(frame(), t)
        return SolverFailed(message, partial=self.dataset(status="failed", failure=message))

    def dataset(self, status: str = "ok", failure: str | None = None) -> xr.Dataset:
        """The schema Dataset of the run; the solver supplies its output
        fields, scheme and attributes through :meth:`output`."""
        wall = _time.perf_counter() - self.t_start
        scene, out = self.scene, self.scene.output
        output = self.output()
        t_probe = out.probe_times(self.frame_times[-1], scene.t_start)
        series = self.history.series(scene, t_probe)
        attrs = {**output.attrs, **self.drift(), "status": status, "geometry": scene.geometry}
        if scene.t_start:  # a run that starts from a state computed before says from what
            attrs.update(t_start=scene.t_start, started_from=scene.parameters.get("started_from", ""))
        if failure:
            attrs["failure"] = failure
        ds = result(
            case=scene.name, method=self.method, scheme=output.scheme,
            x=out.x, y=out.y, z=out.z, times=np.asarray(self.frame_times), fields=output.fields, solid=output.solid,
            probes={pr.name: pr.at(max(2, scene.dim)) for pr in scene.probes} or None,
            t_probe=t_probe if series else None, series=series,
            parameters={"scene": scene.to_dict(), "solver": self.settings},
            dx=self.settings["dx"], n_elements=output.n_elements, n_steps=self.n_steps, wall_seconds=wall,
            compile_seconds=self.compile_seconds, frame_seconds=np.asarray(self.frame_seconds), **attrs,
        )
        if scene.geometry == "axisymmetric":  # a wall of revolution: its whole ring
            for name, units, long_name in RING_LOADS:
                if name in ds:
                    ds[name].attrs.update(units=units, long_name=long_name)
        return ds

    @abstractmethod
    def output(self) -> Output:
        """The :class:`Output` of the frames kept so far."""
