"""A result computed on one period across y, tiled onto the whole
periodic channel (SPEC §4.2: a blast array repeats every row pitch, so a
method may run one period)."""

from __future__ import annotations

import numpy as np
import xarray as xr


def tiled(ds: xr.Dataset, copies: int) -> xr.Dataset:
    """``ds``, a 2D result over one period ``[y0, y0 + P]``, on the channel
    ``copies`` periods wide: every field and the solid mask repeated along
    y (the cell centres continuing at the same spacing), the wall force
    and impulse per metre depth times ``copies`` (the wall is that much
    higher, each period loaded alike), the probes moved ``copies // 2``
    periods up, to the equivalent points of the channel's middle period
    (a probe at ``(W/2) mod P`` lands on the channel's mid-height W/2)."""
    if copies == 1:
        return ds
    y = ds["y"].values
    period = y.size * (y[1] - y[0]) if y.size > 1 else float(ds.attrs["dx"])
    lo, n = y[0] - 0.5 * period / y.size, y.size * copies
    y_all = lo + (np.arange(n) + 0.5) * (copies * period) / n  # (as the channel's own output grid has them)
    data = {}
    for name, var in ds.data_vars.items():
        if "y" in var.dims:
            values = np.concatenate([var.values] * copies, axis=var.dims.index("y"))
            data[name] = (var.dims, values, var.attrs)
        elif name in ("wall_force", "wall_impulse"):
            data[name] = (var.dims, var.values * copies, var.attrs)
        else:
            data[name] = var
    coords = {name: c for name, c in ds.coords.items() if name != "y" and "y" not in c.dims}
    coords["y"] = ("y", y_all, ds["y"].attrs)
    if "probe" in ds.coords:
        coords["probe_y"] = ("probe", ds["probe_y"].values + (copies // 2) * period, ds["probe_y"].attrs)
    out = xr.Dataset(data, coords=coords, attrs=ds.attrs)
    out.attrs["tiled"] = f"one period of {period:g} m across y computed, tiled {copies} times"
    return out
