"""
A blast through a staggered rod array: schlieren
=================================================

The blast of :doc:`plot_blast_wall_loads` passes three staggered layers
of square rods before it reaches the wall. The array repeats every row
pitch (0.04 m) across the channel, so ``one_period=True`` computes one
pitch and the result is tiled onto the whole channel.
"""

import matplotlib.pyplot as plt

import partmesh as pm
from partmesh.compare.metrics import schlieren

scene = pm.scene("blast_array", shape="square", arrangement="staggered", one_period=True)
ds = pm.run(scene, "fv", dx=2e-3, t_end=1.7e-3, progress=False)

# %%
# Numerical schlieren ``exp(−k |∇ρ| / max |∇ρ|)`` at 1.7 ms: the transmitted
# shock on its way to the wall, the reflections between the rods and the
# vortices shed behind them. The rods are drawn black.

picture = schlieren(ds.rho.isel(time=-1))
fig, ax = plt.subplots(figsize=(10, 2.2), layout="constrained")
ax.pcolormesh(ds.x, ds.y, picture, cmap="gray", shading="nearest")
ax.contourf(ds.x, ds.y, ds.solid, levels=[0.5, 1.5], colors="k")
ax.set(aspect="equal", xlabel="x [m]", ylabel="y [m]", title="square rods, staggered, t = 1.7 ms")

# %%
# The wall load up to that time.

fig, ax = plt.subplots(figsize=(6, 3), layout="constrained")
ax.plot(ds.t_probe * 1e3, ds.wall_force / 1e3)
ax.set(xlabel="t [ms]", ylabel="wall force [kN per m depth]")
