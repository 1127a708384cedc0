"""Ensembles: K independent runs of one scene with a stochastic method
(seeds ``seed``, ``seed + 1``, …), run on Dask and averaged into one result
(SPEC §2, §3.3, §8).

The fields are averaged as moments, as DSMC sampling averages them: per
cell the mean density ρ̄, momentum density (ρu)‾ and total energy density
Ē = (p/(γ − 1) + ½ρ|u|²)‾ of the members, then

    u = (ρu)‾/ρ̄,   p = (γ − 1)(Ē − ½ ρ̄ |u|²),   e = p/((γ − 1) ρ̄),

so K members of N particles give what one run of K·N particles would.
Time series (probe pressures, wall force and impulse) are linear in the
moments and are averaged as they are.
"""

from __future__ import annotations

import json

import numpy as np

from partmesh.cases import registry
from partmesh.cases.checks import integer
from partmesh.cases.errors import InputError
from partmesh.cluster import dask_client, local_workers, threads_per_run


def run_ensemble(scene, method: str, ensembles: int, seed: int = 0, scheduler: str | None = None,
                 workers: int | None = None, **settings):
    """The ensemble average of ``ensembles`` runs of ``scene`` with
    ``method`` (which must take a ``seed``), seeds ``seed`` … ``seed +
    ensembles − 1``, run on the Dask scheduler at ``scheduler`` or on a
    LocalCluster of ``workers`` processes (default: one per core)."""
    if not registry.method(method).takes_seed:
        raise InputError(f"method {method} is deterministic: ensembles need a method with a seed (dsmc).")
    ensembles, seed = integer("ensembles", ensembles, 1), integer("seed", seed, 0)
    # bad settings refused here, not on the workers; the last seed is the largest
    registry.method(method).checked(scene, {**settings, "seed": seed + ensembles - 1})
    seeds = [seed + k for k in range(ensembles)]
    n_workers = local_workers(ensembles, workers)
    threads = None if scheduler else threads_per_run(n_workers)
    with dask_client(scheduler, n_workers) as client:
        futures = [client.submit(_member, scene, method, s, threads, settings, pure=False) for s in seeds]
        members = client.gather(futures)
    return ensemble_average(members, scene.gamma)


def _member(scene, method, seed, threads, settings):
    """One member run (on a worker): ``threads`` numba threads if given."""
    if threads:
        import numba  # (lazy: numba loads only in a worker that runs particles)

        numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    chosen = registry.method(method)
    return chosen.solve(scene, chosen.checked(scene, {**settings, "seed": seed}))


def ensemble_average(members: list, gamma: float):
    """One schema Dataset from member results of the same scene, method and
    settings (different seeds): moments averaged (module docstring), time
    series averaged; ``wall_seconds`` and ``n_elements`` are the members'
    totals (the cost and the particles behind the average)."""
    first = members[0]
    K = len(members)
    fields = [name for name in first.data_vars if "time" in first[name].dims]
    out = first.copy(deep=True)
    mean = {name: sum(m[name] for m in members) / K
            for name in first.data_vars if name not in fields and "t_probe" in first[name].dims}
    if {"rho", "u", "p"} <= set(fields):
        velocities = [q for q in ("u", "v") if q in fields]
        rho = sum(m["rho"] for m in members) / K
        momentum = {q: sum((m["rho"] * m[q]).where(m["rho"] > 0, 0.0) for m in members) / K for q in velocities}
        energy = sum((m["p"] / (gamma - 1.0) + 0.5 * m["rho"] * sum(m[q] ** 2 for q in velocities))
                     .where(m["rho"] > 0, 0.0) for m in members) / K
        speed = {q: momentum[q] / rho for q in velocities}
        p = (gamma - 1.0) * (energy - 0.5 * rho * sum(speed[q] ** 2 for q in velocities))
        mean.update(rho=rho, p=p, **speed)
        if "e" in fields:
            mean["e"] = p / ((gamma - 1.0) * rho)
    for name in fields:
        mean.setdefault(name, sum(m[name] for m in members) / K)
    for name, value in mean.items():
        out[name].values = np.asarray(value.values, dtype=first[name].dtype)
    parameters = json.loads(first.attrs["parameters"])
    parameters["solver"]["ensembles"] = K  # (its seed is the first member's)
    out.attrs.update(
        ensembles=K, seeds=json.dumps([_seed(m) for m in members]),
        n_elements=int(sum(m.attrs["n_elements"] for m in members)),
        n_steps=int(max(m.attrs["n_steps"] for m in members)),
        wall_seconds=float(sum(m.attrs["wall_seconds"] for m in members)),
        compile_seconds=float(max(m.attrs["compile_seconds"] for m in members)),
        parameters=json.dumps(parameters),
        status="ok" if all(m.attrs.get("status", "ok") == "ok" for m in members) else "failed",
    )
    return out


def _seed(ds) -> int:
    """The seed a member ran with."""
    return json.loads(ds.attrs["parameters"])["solver"]["seed"]
