"""``partmesh warm``: the kernels of several methods compiled side by side, one process per method.

numba keeps what it compiles on disk (``cache=True``) and JAX keeps its compiled steps in the persistent
compilation cache (:mod:`partmesh.gridref.jax_setup`), so a method compiles once per install and grid size.
That first compile is long and runs on one core (the demo's runs on a 2-core machine: sph 20 to 25 s, dsmc 12
to 15 s, fv 6 s; more where a scene needs dsmc's r–z or 3D kernels): a study whose first runs compile method
after method waits for the sum. :func:`warm` runs a short stretch of each method's runs in a process of its
own, as many at once as there are cores; the runs that follow in the calling process load the compiled code
from disk, and their timings hold no compile. Where everything is compiled already it costs each process its
imports, loading the cached code and a few steps (the demo's: 9-10 s on two cores).
"""

from __future__ import annotations

import multiprocessing
import os
import time
from concurrent.futures import ProcessPoolExecutor

from partmesh.cases.errors import InputError
from partmesh.cases.registry import get
from partmesh.dispatch import run

#: the fraction of a scene's ``t_end`` a warming run goes to: a few steps and outputs, every kernel of both
FRACTION = 0.02


def _compiled(method: str, runs: list[tuple[str, dict]]) -> float:
    """Seconds ``method``'s ``runs`` (scene name, settings) spent compiling (in a worker process)."""
    seconds = 0.0
    for name, settings in runs:
        scene = get(name)
        settings = {"t_end": FRACTION * scene.t_end, **settings, "progress": False}
        seconds += run(scene, method, **settings).attrs["compile_seconds"]
    return seconds


def warm(plan: dict[str, list[tuple[str, dict]]], processes: int | None = None, progress: bool = True) -> dict:
    """Compile what the runs of ``plan`` (method -> its runs, each ``(scene name, settings)``, run to
    :data:`FRACTION` of the scene's ``t_end`` unless the settings give one) need, each method in a process of
    its own, at most ``processes`` (default: the cores) at a time, the methods in
    the order given (put the longest first). Returns method -> the seconds its runs spent compiling, and
    ``"wall"`` -> the seconds the whole took."""
    if processes is not None and (isinstance(processes, bool) or not isinstance(processes, int) or processes < 1):
        raise InputError(f"processes must be a whole number of at least 1 (or None: the cores); got {processes!r}.")
    processes = max(1, min(processes or os.cpu_count() or 1, len(plan)))
    if progress:
        print(f"compiling the kernels of {', '.join(plan)} in {processes} process{'es' * (processes > 1)} "
              "(first run only)", flush=True)
    started = time.perf_counter()
    seconds = {}
    # spawn, not fork: a forked child would inherit the caller's numba and JAX threads in an unknown state
    with ProcessPoolExecutor(processes, mp_context=multiprocessing.get_context("spawn")) as pool:
        futures = {method: pool.submit(_compiled, method, runs) for method, runs in plan.items()}
        for method, future in futures.items():
            seconds[method] = future.result()
            if progress:
                print(f"  {method}: {seconds[method]:.1f} s compiling", flush=True)
    seconds["wall"] = time.perf_counter() - started
    if progress:
        print(f"  compiled in {seconds['wall']:.1f} s", flush=True)
    return seconds
