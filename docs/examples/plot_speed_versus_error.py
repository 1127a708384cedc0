"""
Speed against error
===================

What accuracy does each method buy for a second of computing? Sod's
shock tube at several resolutions per method: the L1 error of the density
against the exact solution, against the solver's wall time (compilation
excluded). A method is worth its cost where no other is both faster and
more accurate (the Pareto front, :func:`partmesh.compare.pareto.pareto_front`).
"""

import matplotlib.pyplot as plt

import partmesh as pm
from partmesh.compare.pareto import pareto_front
from partmesh.compare.report import table

scene = pm.scene("sod")
ladders = {"fv": (1 / 100, 1 / 200, 1 / 400, 1 / 800), "sph": (1 / 200, 1 / 400), "dsmc": (1 / 100, 1 / 200)}


def timed_run(method, dx):
    """A run after a first one at the same size (untimed): the first call at a
    new size pays one-off costs (buffers, caches) that are not the method's."""
    settings = {"dx": dx, "progress": False, **({"seed": 1} if method == "dsmc" else {})}
    if method == "fv":
        pm.run(scene, method, **settings)
    return pm.run(scene, method, **settings)


runs = [timed_run(method, dx) for method, spacings in ladders.items() for dx in spacings]
errors = table(runs, scene.exact(runs[0].time.values))

# %%
# Error against cost, log–log; the runs on the Pareto front are ringed.

front = pareto_front(errors.wall_seconds, errors.rho_L1)
fig, ax = plt.subplots(figsize=(6.5, 4.2), layout="constrained")
for k, (method, rows) in enumerate(errors.groupby("method", sort=False)):
    ax.loglog(rows.wall_seconds, rows.rho_L1, "o-", color=f"C{k}", label=method)
ax.loglog(errors.wall_seconds[front], errors.rho_L1[front], "o", ms=12, mfc="none", mec="k", label="Pareto front")
ax.set(xlabel="wall time [s]", ylabel="L1 error of the density [kg m-3]", title="sod, t = 0.2 s")
ax.legend()

# %%
errors[["method", "dx", "n_elements", "wall_seconds", "rho_L1"]]
