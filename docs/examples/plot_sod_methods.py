"""
Sod's shock tube: every gas method against the exact solution
==============================================================

The same scene, run with the finite-volume reference (``fv``), gas SPH
(``sph``) and equilibrium DSMC (``dsmc``). Every method writes its fields
on the scene's output grid, so each result subtracts from the exact
solution (and from the others) directly.
"""

import matplotlib.pyplot as plt

import partmesh as pm
from partmesh.compare.report import table

scene = pm.scene("sod")
runs = {
    "fv": pm.run(scene, "fv", dx=2.5e-3, progress=False),
    "sph": pm.run(scene, "sph", dx=2.5e-3, progress=False),
    "dsmc": pm.run(scene, "dsmc", dx=5e-3, seed=1, progress=False),
}
exact = scene.exact(runs["fv"].time.values)

# %%
# Density, velocity and pressure at t = 0.2 s. DSMC's statistical scatter
# is drawn light under its 9-cell running mean.

fig, axes = plt.subplots(1, 3, figsize=(11, 3.4), layout="constrained")
for ax, field in zip(axes, ("rho", "u", "p")):
    for method, color in (("dsmc", "C2"), ("sph", "C1"), ("fv", "C0")):  # (the noisiest underneath)
        ds = runs[method]
        profile = ds[field].isel(time=-1)
        if method == "dsmc":
            ax.plot(ds.x, profile, color=color, lw=0.6, alpha=0.3)
            profile = profile.rolling(x=9, center=True, min_periods=5).mean()
        ax.plot(ds.x, profile, color=color, lw=1.4, label=method)
    ax.plot(exact.x, exact[field].isel(time=-1), "k--", lw=1, label="exact")
    ax.set_xlabel("x [m]")
    ax.set_title(f"{exact[field].attrs['long_name'].split(',')[0]} [{exact[field].attrs['units']}]")
axes[0].legend()

# %%
# The error of every field against the exact solution, beside each run's
# cost (``wall_seconds`` excludes compilation, kept apart in
# ``compile_seconds``).

errors = table(list(runs.values()), exact, list(runs))
errors[["run", "n_elements", "wall_seconds", "rho_L1", "u_L1", "p_L1"]]
