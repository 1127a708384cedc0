"""Where independent runs go: a Dask cluster (SPEC §8).

Sweeps and ensembles are independent runs. They run on ``dask.distributed``:
a :class:`~distributed.LocalCluster` of single-threaded worker processes on
this machine by default, or the scheduler at ``scheduler`` (a real cluster,
whose workers keep their own signal handling).
Each run inside a local worker uses its share of the cores for its numba
threads, so K workers on C cores do not oversubscribe them.
"""

from __future__ import annotations

import os
from contextlib import contextmanager

from partmesh.cases.checkpoint import watch_signals_for_runs
from partmesh.cases.errors import InputError


def local_workers(runs: int, workers: int | None = None) -> int:
    """Worker processes of a local cluster for ``runs`` runs: ``workers``
    if given, else one per core, never more than the runs."""
    if workers is not None and workers < 1:
        raise InputError(f"workers must be a whole number >= 1; got {workers}.")
    return max(1, min(runs, workers or os.cpu_count() or 1))


@contextmanager
def dask_client(scheduler: str | None = None, workers: int = 1):
    """A ``distributed.Client``: of the scheduler at address ``scheduler``,
    or of a new LocalCluster with ``workers`` single-threaded worker
    processes (closed on exit), in which Ctrl-C or SIGTERM asks the runs
    to stop between two steps (:func:`partmesh.cases.checkpoint.watch_signals_for_runs`)
    instead of ending the process."""
    from distributed import Client, LocalCluster  # (lazy: Dask, ~1 s to import, only for runs on a cluster)

    if scheduler:
        with Client(scheduler) as client:
            yield client
        return
    # the scheduler's HTTP server on a free port: sweeps side by side do not fight over 8787
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        client.run(watch_signals_for_runs)
        yield client


def threads_per_run(workers: int) -> int:
    """Numba threads for one run when ``workers`` runs share this machine."""
    return max(1, (os.cpu_count() or 1) // workers)
