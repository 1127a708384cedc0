"""Atomic netCDF4 writing and checked reading of partmesh results (SPEC §2, §9)."""

from __future__ import annotations

import os
import tempfile
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import xarray as xr

from partmesh.compare.schema import SchemaError, validate


def write(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Validate ``ds`` and write it to ``path`` as netCDF4, atomically: the data
    go to a temporary file in the same folder, which is then renamed, so a
    reader never sees a half-written result."""
    validate(ds)
    return _write_atomically(ds, path)


#: variables of a particle snapshot (SPEC §2), each on the dimension ``particle``
PARTICLE_VARIABLES = ("x", "y", "u", "v", "rho", "p", "m", "h", "kind")


def particle_snapshot(x, v, rho, p, m, H, kind, kinds: dict, case: str, method: str, time: float,
                      mass_units: str = "kg m-(3-d)") -> xr.Dataset:
    """A particle snapshot (SPEC §2) of positions ``x`` and velocities ``v``
    (n, d), density, pressure, mass, support radius ``H`` (written as
    h = H/2) and ``kind`` (ints, named by ``kinds``: name -> value)."""
    dim = x.shape[1]
    variables = {"x": (x[:, 0], "m", "position x"), "u": (v[:, 0], "m s-1", "velocity x"),
                 "rho": (rho, "kg m-3", "density"), "p": (p, "Pa", "pressure"),
                 "m": (m, mass_units, "mass (per unit length/area of the missing dimensions)"),
                 "h": (0.5 * H, "m", "smoothing length h = H/2 (H: kernel support radius)")}
    if dim == 2:
        variables.update(y=(x[:, 1], "m", "position y"), v=(v[:, 1], "m s-1", "velocity y"))
    ds = xr.Dataset({name: ("particle", a, {"units": units, "long_name": long})
                     for name, (a, units, long) in variables.items()})
    ds["kind"] = ("particle", np.asarray(kind, np.int8), {"long_name": "particle kind",
                                                          "flag_values": list(kinds.values()),
                                                          "flag_meanings": " ".join(kinds)})
    ds.attrs.update(case=case, method=method, time=time, Conventions="CF-1.10")
    return ds


def write_particles(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Write a particle snapshot (SPEC §2: ``x, y, u, v, rho, p, m, h`` and
    ``kind`` on the dimension ``particle``; ``y, v`` only in 2D) atomically."""
    need = [n for n in PARTICLE_VARIABLES if n not in ("y", "v")]
    missing = [n for n in need if n not in ds or ds[n].dims != ("particle",)]
    if missing:
        raise SchemaError(f"a particle snapshot needs {', '.join(missing)} on the dimension 'particle'.")
    return _write_atomically(ds, path)


def _write_atomically(ds: xr.Dataset, path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        ds.to_netcdf(tmp, engine="netcdf4")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path


@contextmanager
def opened(path: str | os.PathLike):
    """A partmesh result opened lazily (only its coordinates and attributes
    are read until data are asked for), closed on exit; refuses, with one
    sentence, a file that is missing, not netCDF, or not a partmesh result."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"result file {str(path)!r} does not exist.")
    try:
        ds = xr.open_dataset(path, engine="netcdf4")
    except (OSError, ValueError) as err:
        raise SchemaError(f"{str(path)!r} is not a readable netCDF file ({err}).") from None
    with ds:
        if "partmesh_version" not in ds.attrs:
            raise SchemaError(f"{str(path)!r} is not a partmesh result (it has no 'partmesh_version' attribute).")
        try:
            validate(ds)
        except SchemaError as err:
            raise SchemaError(f"{str(path)!r} is a damaged partmesh result: {err}") from None
        yield ds


def read(path: str | os.PathLike) -> xr.Dataset:
    """A partmesh result read into memory (checked as :func:`opened` checks it)."""
    with opened(path) as ds:
        try:
            return ds.load()
        except (OSError, ValueError) as err:
            raise SchemaError(f"{str(path)!r} is not a readable netCDF file ({err}).") from None
