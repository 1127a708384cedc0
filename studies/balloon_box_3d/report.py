"""The record of studies/balloon_box_3d from its runs (see README.md):
mid-plane density of every run at the seed's 0.54 ms and the pressure
histories of the probes.

    python studies/balloon_box_3d/report.py [--prefix NAME] RUN.nc [RUN.nc ...]

``--prefix`` names the figures ``NAME_mid_planes.png`` and ``NAME_histories.png``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import partmesh as pm  # noqa: E402

HERE = Path(__file__).parent
P0 = 101325.0


def label(ds) -> str:
    return f"{ds.attrs['method']} dx = {1e3 * ds.attrs['dx']:.3g} mm ({ds.attrs['n_elements']:,} elements)"


def mid_planes(runs, path, t=0.54e-3):
    """Density on the X–Y (z = middle) and X–Z (y = middle) planes of every run at ``t``."""
    fig, axes = plt.subplots(2, len(runs), figsize=(4.2 * len(runs), 6.4), squeeze=False,
                             gridspec_kw={"height_ratios": [1.78, 0.6]})
    for k, ds in enumerate(runs):
        frame = ds["rho"].sel(time=t, method="nearest")
        xy = frame.isel(z=ds.sizes["z"] // 2)
        xz = frame.isel(y=ds.sizes["y"] // 2)
        lo, hi = float(frame.min()), float(frame.max())
        axes[0, k].pcolormesh(ds.x, ds.y, xy.transpose("y", "x"), vmin=lo, vmax=hi, shading="nearest")
        image = axes[1, k].pcolormesh(ds.x, ds.z, xz.transpose("z", "x"), vmin=lo, vmax=hi, shading="nearest")
        axes[0, k].set_title(f"{label(ds)}\nX–Y mid-plane, t = {float(frame.time) * 1e3:.2f} ms", fontsize=8)
        axes[1, k].set_title("X–Z mid-plane", fontsize=8)
        for ax in axes[:, k]:
            ax.set_aspect("equal")
            ax.tick_params(labelsize=7)
        fig.colorbar(image, ax=list(axes[:, k]), label="rho [kg m-3]", shrink=0.8)
    fig.savefig(path, dpi=120)


def histories(runs, path):
    """p/p0 at every probe, each run on one panel per probe (dsmc: one sample of its cell, unsmoothed)."""
    probes = list(runs[0].probe.values)
    fig, axes = plt.subplots(1, len(probes), figsize=(3.6 * len(probes), 3.2), sharey=True)
    for ax, probe in zip(axes, probes):
        for ds in runs:
            ax.plot(ds.t_probe * 1e3, ds["p_probe"].sel(probe=probe) / P0, lw=0.8, label=label(ds))
        ax.set_title(str(probe), fontsize=9)
        ax.set_xlabel("t [ms]", fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("p / p0", fontsize=8)
    axes[0].legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+")
    parser.add_argument("--prefix", default="")
    args = parser.parse_args()
    runs = [pm.read(path) for path in args.runs]
    names = [HERE / f"{args.prefix + '_' if args.prefix else ''}{name}.png" for name in ("mid_planes", "histories")]
    mid_planes(runs, names[0])
    histories(runs, names[1])
    print("written", *names)
