"""
A blast on a wall: the load of each method
==========================================

A Friedlander blast (peak overpressure 10.9 p0) enters a channel at
x = 0 and loads a rigid wall 1 m away (Prasanna Kumar, Patnaik &
Ramamurthi 2018). The scene is one-dimensional, and every method runs it
as such; the wall force is per metre of depth, over the channel's height.
The particle methods run at 4 mm here, to keep the example short;
``studies/blast_array`` holds the converged runs.
"""

import matplotlib.pyplot as plt
import pandas as pd

import partmesh as pm

scene = pm.scene("blast_wall")
runs = {
    "fv": pm.run(scene, "fv", dx=2e-3, progress=False),
    "sph": pm.run(scene, "sph", dx=4e-3, progress=False),
    "dsmc": pm.run(scene, "dsmc", dx=4e-3, seed=1, progress=False),
}

# %%
# Wall force and impulse against time. The force rises as the reflected
# shock forms and decays with the blast's positive phase.

fig, (force, impulse) = plt.subplots(1, 2, figsize=(10, 3.6), layout="constrained")
for method, color in (("dsmc", "C2"), ("sph", "C1"), ("fv", "C0")):  # (the noisiest underneath)
    ds = runs[method]
    wall_force = ds.wall_force / 1e3
    if method == "dsmc":  # its scatter light, under a running mean over 0.05 ms
        force.plot(ds.t_probe * 1e3, wall_force, color=color, lw=0.5, alpha=0.3)
        window = max(1, int(round(5e-5 / float(ds.t_probe[1] - ds.t_probe[0]))))
        wall_force = wall_force.rolling(t_probe=window, center=True, min_periods=1).mean()
    force.plot(ds.t_probe * 1e3, wall_force, color=color, label=method)
    impulse.plot(ds.t_probe * 1e3, ds.wall_impulse, color=color, label=method)
force.set(xlabel="t [ms]", ylabel="wall force [kN per m depth]")
impulse.set(xlabel="t [ms]", ylabel="wall impulse [N s per m depth]")
force.legend()

# %%
# What the scene measures from each run: the peak wall pressure raw and
# fitted back to the shock's arrival (the raw maximum of a captured shock
# carries a start-up spike), the arrival time and the impulse at 3 ms.

quantities = ["wall_peak_pressure_raw", "wall_peak_pressure_fitted", "wall_arrival_time", "wall_impulse_final"]
pd.DataFrame({method: {q: ds.attrs[q] for q in quantities} for method, ds in runs.items()}).T
