"""Run a scene with any registered method.

Methods are found through the ``partmesh.methods`` entry-point group (as
xarray finds its backends): ``fv = "partmesh.gridref.euler.method:METHOD"`` and so
on, each a :class:`~partmesh.cases.method.Method`. No solver module is imported
until a run's settings and memory are checked (the particle methods'
settings name numba's kernels, so numba may come first), and another
package can add a method by declaring an entry point of its own.
"""

from __future__ import annotations

from partmesh.cases import registry
from partmesh.cases.errors import Unsupported
from partmesh.cases.tiling import tiled
from partmesh.ensembles import run_ensemble


def run(scene, method: str, ensembles: int = 1, scheduler: str | None = None, workers: int | None = None,
        **settings):
    """Run ``scene`` (a Scene or a case name) with ``method`` and return the
    schema Dataset, with the scene's measured quantities in its attributes
    (their names listed in the attribute ``measured_quantities``). A scene
    of one period across y (``tiles`` > 1) is tiled onto its whole channel.

    ``settings`` go to the solver (``dx``, ``cfl``, ``t_end``, ``progress``, and
    method-specific ones). ``ensembles`` > 1 runs that many seeds of a
    stochastic method on Dask (the scheduler at ``scheduler``, or a
    LocalCluster of ``workers`` processes) and returns their average
    (:func:`partmesh.ensembles.run_ensemble`). A scene with a ``precursor``
    (:class:`~partmesh.cases.scene.Precursor`) runs it first and starts from
    its result. A run that fails raises
    :class:`~partmesh.cases.errors.SolverFailed` carrying the partial result.
    """
    if isinstance(scene, str):
        scene = registry.get(scene)
    chosen = registry.method(method)
    refusal = chosen.refusal(scene)
    if refusal:
        raise Unsupported(refusal)
    if scene.precursor is not None:  # the run that computes the scene's starting state comes first
        chosen.checked(scene, settings)  # (bad settings are refused before it)
        pre = scene.precursor
        scene = pre.start(run(pre.scene, pre.method, progress=settings.get("progress", True), **pre.settings))
    if ensembles != 1:
        settings.pop("progress", None)  # (workers show none)
        ds = run_ensemble(scene, method, ensembles, scheduler=scheduler, workers=workers, **settings)
    else:
        ds = chosen.solve(scene, chosen.checked(scene, settings))
    if getattr(scene, "tiles", 1) > 1:
        ds = tiled(ds, scene.tiles)
    if scene.measure is not None:
        quantities = scene.measure(ds)
        ds.attrs.update(quantities)
        ds.attrs["measured_quantities"] = " ".join(quantities)
    return ds


#: a run shorter than this many seconds is timed as the best of :data:`REPEATS` (:func:`best_timed_run`)
SHORT_RUN = 2.0
#: how many times a short run is made for its timing
REPEATS = 3


def best_timed_run(scene, method: str, repeats: int = REPEATS, short: float = SHORT_RUN, **settings):
    """:func:`run`, whose ``wall_seconds`` (solver time, compile apart) is the
    best of ``repeats`` runs where the first took less than ``short``
    seconds: a short run's time is at the mercy of first-call costs and of
    whatever else the machine runs, and the least of several is the time
    the method needs. The runs are the same run (seeded), so the first's
    fields are returned; attrs add ``wall_seconds_runs`` (every run's solver
    time, the first first) and ``timing`` (a sentence saying how it was
    timed)."""
    ds = run(scene, method, **settings)
    times = [ds.attrs["wall_seconds"]]
    if times[0] < short:
        times += [run(scene, method, **settings).attrs["wall_seconds"] for _ in range(repeats - 1)]
    ds.attrs["wall_seconds"] = min(times)
    ds.attrs["wall_seconds_runs"] = times
    ds.attrs["timing"] = (f"solver time, best of {len(times)} runs" if len(times) > 1
                          else f"solver time of one run (over {short:g} s)")
    return ds
