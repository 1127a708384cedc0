"""
A TNT charge on the ground against Kingery–Bulmash
==================================================

One kilogram of TNT on a rigid ground, modelled as a Brode balloon (an
ideal gas of γ 1.4 at the charge's density holding its 4.184 MJ), makes a
hemispherical blast. The ground gauges ``Z1`` … ``Z12`` sit at those
scaled distances Z = R / W^(1/3) [m/kg^(1/3)], where the Kingery–Bulmash
fits (Swisdak 1994) give the blast engineer's reference values.

``surface_burst`` runs the r–z quadrant (x is the radius from the axis, y
the height above the ground); ``surface_burst_1d`` is the sphere of 2 kg
in free air that the hemisphere mirrors, the same flow in 1D. The r–z run
here uses 4 cm cells to stay short; ``studies/surface_burst`` holds the
1 cm level and the particle methods. ``charge="jwl"`` replaces the balloon
by TNT itself, detonated from its centre, its products following the JWL
equation of state (``fv`` in 1D and r–z; ``sph`` in r–z, its particles
carrying the products the remapped sphere holds).
"""

import json

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import partmesh as pm
from partmesh.compare.exact import kingery_bulmash

# the 1D sphere's cells are its 16 m over n_out (extent 16: out to Z12, as the r–z quadrant; t_end 36 ms)
sphere = dict(extent=16.0, t_end=0.036)
runs = {
    "1D sphere, 16 mm": pm.run(pm.scene("surface_burst_1d", n_out=1000, **sphere), "fv", progress=False),
    "1D sphere, 4 mm": pm.run(pm.scene("surface_burst_1d", n_out=4000, **sphere), "fv", progress=False),
    "r–z, 4 cm": pm.run(pm.scene("surface_burst"), "fv", dx=0.04, progress=False),
    "1D sphere, JWL TNT, 4 mm": pm.run(pm.scene("surface_burst_1d", n_out=4000, charge="jwl", **sphere), "fv",
                                       progress=False),
}
gauges = ["Z1", "Z1.5", "Z2", "Z3", "Z5", "Z8", "Z12"]
Z = np.array([float(g[1:]) for g in gauges])

# %%
# Peak overpressure and positive impulse against scaled distance. The raw
# peak is the gauge's maximum; a captured shock is smeared over a few
# cells, so that maximum falls short by the decay across them. The fitted
# peak reads the flow behind the front and carries it back to the shock
# (:func:`partmesh.compare.metrics.shock_fitted_peak`; NaN where a front
# is too wide to fit behind, none here).

z = np.geomspace(0.5, 16.0, 200)
fig, (peak, impulse) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
peak.loglog(z, kingery_bulmash.scaled_value("incident_overpressure", z) / 1e3, "k", label="Kingery–Bulmash")
impulse.loglog(z, kingery_bulmash.scaled_value("incident_impulse", z), "k", label="Kingery–Bulmash")
for (label, ds), color in zip(runs.items(), ("C1", "C0", "C2", "C3")):
    raw = [ds.attrs[f"{g}_peak_overpressure"] / 1e3 for g in gauges]
    fitted = [ds.attrs[f"{g}_peak_overpressure_fitted"] / 1e3 for g in gauges]
    peak.plot(Z, raw, "o", mfc="none", color=color, label=f"{label}, raw")
    peak.plot(Z, fitted, "s", color=color, label=f"{label}, fitted")
    impulse.plot(Z, [ds.attrs[f"{g}_positive_impulse"] for g in gauges], "o", color=color, label=label)
peak.set(xlabel="Z [m/kg$^{1/3}$]", ylabel="peak overpressure [kPa]")
impulse.set(xlabel="Z [m/kg$^{1/3}$]", ylabel="positive impulse [Pa s]")
peak.legend(fontsize="small")
impulse.legend(fontsize="small")

# %%
# Each run's gauges over the fits' values. Near the charge the balloon's
# peak is too high (the 4 mm sphere: +20 % at Z = 1, +10 % at Z = 1.5):
# it releases the detonation energy at once, at the charge's density,
# where a real charge's products expand with their own equation of
# state. From Z = 2 on, the fitted peak of the finer 1D sphere is within
# 5 % of the fits. The positive phase is shorter than the fits' (the
# 4 mm sphere: by 64 % at Z = 1, 13 % at Z = 12) and the impulse 13–26 %
# low at every resolution: the balloon's blast carries the charge's
# energy in a shorter, steeper wave. TNT detonated with its products' JWL
# equation of state brings the near field closer (at 4 mm, +11 % at Z = 1
# and +6 % at Z = 1.5) but leaves the impulse as low (0.74–0.86 of the fits
# from Z = 1 on): the fits' charges also burnt their products in the air
# behind the blast (TNT's afterburning, which releases more than its
# detonation energy again), which neither charge here does.

table = pd.DataFrame({
    (label, quantity): [ds.attrs[f"{g}_{key}"] / ds.attrs[f"{g}_{reference}_kb"] for g in gauges]
    for label, ds in runs.items()
    for quantity, key, reference in (("peak raw", "peak_overpressure", "peak_overpressure"),
                                     ("peak fitted", "peak_overpressure_fitted", "peak_overpressure"),
                                     ("duration", "positive_duration", "positive_duration"),
                                     ("impulse", "positive_impulse", "positive_impulse"))
}, index=gauges)
table.round(3)

# %%
# The blast at 10 ms in the r–z quadrant: a hemispherical front, its
# overpressure phase followed by the suction of the negative phase.

ds = runs["r–z, 4 cm"]
p0 = json.loads(ds.attrs["parameters"])["scene"]["p0"]
frame = ds.p.sel(time=10e-3, method="nearest").sel(x=slice(0, 8), y=slice(0, 8))
fig, ax = plt.subplots(figsize=(5, 4.4), layout="constrained")
((frame - p0) / 1e3).plot(ax=ax, cmap="RdBu_r", center=0.0, cbar_kwargs={"label": "overpressure [kPa]"})
ax.set(xlabel="r [m]", ylabel="z [m]", aspect="equal",
       title=f"t = {float(frame.time) * 1e3:.1f} ms")
