"""
Prins' mound of water: long waves against dispersive theory
===========================================================

A box of water raised by 0.12 m over the first 0.61 m of a flume 0.7 m
deep is released at rest (Prins 1958). The shallow-water model (``swe``)
has no dispersion; linear dispersive theory
(:func:`partmesh.compare.exact.linear_waves`) has it. At the gauges the
long-wave model keeps the wave's front steep, where dispersion spreads it
into a train of waves.
"""

import matplotlib.pyplot as plt

import partmesh as pm

scene = pm.scene("prins_mound", t_end=5.0)
ds = pm.run(scene, "swe", dx=0.02, progress=False)
theory = scene.exact(ds.time.values)

# %%
# The surface elevation at the gauges 2 m and 6 m from the wall.

fig, axes = plt.subplots(2, 1, figsize=(8, 5), sharex=True, layout="constrained")
for ax, gauge in zip(axes, ("x2", "x6")):
    ax.plot(ds.t_probe, ds.eta_probe.sel(probe=gauge) * 100, label="shallow water (swe)")
    ax.plot(theory.t_probe, theory.eta_probe.sel(probe=gauge) * 100, "k-", lw=1, label="linear dispersive theory")
    ax.set(ylabel="η [cm]", title=f"gauge at x = {gauge[1:]} m")
axes[-1].set_xlabel("t [s]")
axes[0].legend()
