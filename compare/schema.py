"""The common result schema (SPEC §2): what every solver returns and every
comparison reads.

A result is one :class:`xarray.Dataset` with

* coordinates ``time`` [s], ``x`` [m] (and ``y`` [m] in 2D) — the scene's
  output grid, so two results subtract directly; ``probe`` (str) with
  ``probe_x``/``probe_y`` and ``t_probe`` [s] for time series;
* fields on ``(time, [y,] x)``: gas ``rho, u, v, p, e``; water ``eta, u, h``;
  ``solid`` on ``([y,] x)``;
* series on ``(t_probe, probe)``: ``p_probe``, ``eta_probe``; on ``(t_probe,)``:
  ``wall_force``, ``wall_impulse``;
* the attributes of :data:`REQUIRED_ATTRS`, ``geometry`` (``planar``;
  ``axisymmetric``: x is the radius r from the axis and y is z, and forces
  are over whole rings; ``spherical``; ``radial`` for radial water), and
  ``source_revision`` (the git commit of the code) when run from a checkout.

:func:`result` builds such a Dataset with units and long names filled in;
:func:`validate` accepts one or raises :class:`SchemaError` naming what is
wrong.
"""

from __future__ import annotations

import datetime as _dt
import functools
import json
import subprocess
from importlib import metadata
from pathlib import Path

import numpy as np
import xarray as xr

#: the entry-point group methods register in (:mod:`partmesh.dispatch`), this package's and any other's
METHOD_GROUP = "partmesh.methods"
#: the methods this package registers, valid where its entry points are not installed (a source tree)
BUILT_IN = ("dsmc", "fv", "hybrid", "sph", "swe", "wcsph")
#: what a result's ``method`` may name besides a method
EXACT = "exact"


def methods() -> tuple[str, ...]:
    """The methods a result may name: this package's, every method
    registered in :data:`METHOD_GROUP` (another package's too), and
    ``exact``."""
    return (*sorted({*BUILT_IN, *(ep.name for ep in metadata.entry_points(group=METHOD_GROUP))}), EXACT)


#: name -> (units, long_name) for every variable the schema knows.
VARIABLES: dict[str, tuple[str, str]] = {
    "time": ("s", "output time"),
    "x": ("m", "cell-centre x of the output grid"),
    "y": ("m", "cell-centre y of the output grid"),
    "z": ("m", "cell-centre z of the output grid"),
    "t_probe": ("s", "probe sampling time"),
    "probe": ("1", "probe name"),
    "probe_x": ("m", "probe x position"),
    "probe_y": ("m", "probe y position"),
    "probe_z": ("m", "probe z position"),
    "rho": ("kg m-3", "density"),
    "u": ("m s-1", "x velocity"),
    "v": ("m s-1", "y velocity"),
    "w": ("m s-1", "z velocity"),
    "p": ("Pa", "pressure"),
    "e": ("J kg-1", "specific internal energy"),
    "Y": ("1", "mass fraction of detonation products"),
    "alpha": ("1", "volume fraction of detonation products"),
    "eta": ("m", "free-surface elevation above still water"),
    "h": ("m", "water depth"),
    "solid": ("1", "solid mask (1 inside obstacles, 0 in fluid)"),
    "p_probe": ("Pa", "pressure at probe"),
    "eta_probe": ("m", "free-surface elevation at gauge"),
    "wall_force": ("N m-1", "force on the target wall per metre depth, integral of (p_wall - p0) dy"),
    "wall_impulse": ("N s m-1", "wall impulse per metre depth, time integral of wall_force"),
}

FIELDS = ("rho", "u", "v", "w", "p", "e", "Y", "alpha", "eta", "h")
SERIES_BY_PROBE = ("p_probe", "eta_probe")
SERIES = ("wall_force", "wall_impulse")

REQUIRED_ATTRS = (
    "case", "method", "scheme", "dx", "n_elements", "n_steps", "wall_seconds",
    "compile_seconds", "parameters", "partmesh_version", "Conventions", "created",
)


class SchemaError(ValueError):
    """A Dataset (or file) that does not follow the partmesh result schema."""


def version() -> str:
    """The installed partmesh version."""
    try:
        return metadata.version("partmesh")
    except metadata.PackageNotFoundError:  # running from a source tree
        return "0+unknown"


@functools.cache
def source_revision() -> str | None:
    """The git commit of the source tree this module was imported from,
    with ``+dirty`` when that tree holds uncommitted changes to tracked
    files; None outside a git checkout (an installed wheel) or without git.
    Read once per process, when the first run starts
    (:class:`~partmesh.cases.history.RunRecord`), so a run names the code
    it loaded even if the tree changes while it runs, and an import runs
    no git."""
    root = Path(__file__).resolve().parent.parent

    def git(*args) -> str:
        return subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True, timeout=10,
                              check=True).stdout.strip()

    try:
        top, commit = git("rev-parse", "--show-toplevel", "HEAD").splitlines()
        if Path(top).resolve() != root:
            return None
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.SubprocessError):
        return None
    return commit + ("+dirty" if dirty else "")



def _spatial_dims(ndim: int) -> tuple[str, ...]:
    """The field layout's spatial dimensions, x last: ``(x,)``, ``(y, x)``, ``(z, y, x)``."""
    return ("z", "y", "x")[3 - ndim:]


def load_result_modules() -> None:
    """Load what building the first result in a process loads: xarray looks
    for dask arrays among the data of every variable it makes, importing
    ``dask.array`` the first time (about 0.4 s, measured; dask is installed
    for ensembles and sweeps). A caller with a compile under way in another
    thread loads it meanwhile."""
    import dask.array  # noqa: F401


def result(
    *,
    case: str,
    method: str,
    scheme: str,
    x: np.ndarray,
    times: np.ndarray,
    fields: dict[str, np.ndarray],
    y: np.ndarray | None = None,
    z: np.ndarray | None = None,
    solid: np.ndarray | None = None,
    probes: dict[str, tuple[float, float]] | None = None,
    t_probe: np.ndarray | None = None,
    series: dict[str, np.ndarray] | None = None,
    parameters: dict | None = None,
    dx: float,
    n_elements: int = 0,
    n_steps: int = 0,
    wall_seconds: float = 0.0,
    compile_seconds: float = 0.0,
    long_names: dict[str, str] | None = None,
    **attrs,
) -> xr.Dataset:
    """Assemble a schema Dataset from plain arrays.

    ``fields`` maps field names to arrays of shape ``(time, [[z,] y,] x)``
    (``z`` only with ``y``); probes are ``(x, y)`` or, in 3D, ``(x, y, z)``;
    ``series`` maps ``p_probe``/``eta_probe`` to ``(t_probe, probe)`` arrays
    and ``wall_force``/``wall_impulse`` to ``(t_probe,)`` arrays.
    ``long_names`` overrides the default long name of a variable (e.g. to say
    which velocity ``u`` is in a water result). Extra keyword arguments
    become attributes.
    """
    if z is not None and y is None:
        raise SchemaError("a result with a z coordinate needs a y coordinate too.")
    axes = {name: c for name, c in (("x", x), ("y", y), ("z", z)) if c is not None}
    dims = _spatial_dims(len(axes))
    coords: dict = {"time": ("time", np.asarray(times, float))}
    coords.update({name: (name, np.asarray(c, float)) for name, c in axes.items()})
    data_vars: dict = {name: (("time",) + dims, np.asarray(a, float)) for name, a in fields.items()}
    if solid is not None:
        data_vars["solid"] = (dims, np.asarray(solid, np.int8))
    if probes:
        names = list(probes)
        coords["probe"] = ("probe", np.array(names, dtype=object))
        coords["probe_x"] = ("probe", np.array([probes[n][0] for n in names], float))
        coords["probe_y"] = ("probe", np.array([probes[n][1] for n in names], float))
        if z is not None:
            coords["probe_z"] = ("probe", np.array([probes[n][2] for n in names], float))
    if t_probe is not None:
        coords["t_probe"] = ("t_probe", np.asarray(t_probe, float))
    for name, a in (series or {}).items():
        data_vars[name] = (("t_probe", "probe") if name in SERIES_BY_PROBE else ("t_probe",), np.asarray(a, float))
    ds = xr.Dataset(data_vars, coords=coords)
    for name in list(ds.variables):
        units, long_name = VARIABLES[name]
        ds[name].attrs.update(units=units, long_name=(long_names or {}).get(name, long_name))
    ds.attrs.update(
        case=case, method=method, scheme=scheme, dx=float(dx), n_elements=int(n_elements),
        n_steps=int(n_steps), wall_seconds=float(wall_seconds), compile_seconds=float(compile_seconds),
        parameters=json.dumps(parameters or {}, sort_keys=True, default=float),
        partmesh_version=version(), Conventions="CF-1.10",
        created=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        status="ok", geometry="planar",
    )
    if source_revision():
        ds.attrs["source_revision"] = source_revision()
    ds.attrs.update(attrs)
    return ds


def validate(ds: xr.Dataset) -> xr.Dataset:
    """Return ``ds`` unchanged if it follows the schema, else raise
    :class:`SchemaError` with one sentence naming the first problem found."""
    if not isinstance(ds, xr.Dataset):
        raise SchemaError(f"a partmesh result must be an xarray.Dataset, got {type(ds).__name__}.")
    missing = [a for a in REQUIRED_ATTRS if a not in ds.attrs]
    if missing:
        raise SchemaError(f"result is missing the required attribute(s) {', '.join(missing)}.")
    if ds.attrs["method"] not in methods():
        raise SchemaError(f"attribute 'method' is {ds.attrs['method']!r}; allowed: {', '.join(methods())}.")
    if ds.attrs["Conventions"] != "CF-1.10":
        raise SchemaError(f"attribute 'Conventions' must be 'CF-1.10', got {ds.attrs['Conventions']!r}.")
    try:
        json.loads(ds.attrs["parameters"])
    except (TypeError, ValueError) as err:
        raise SchemaError(f"attribute 'parameters' must be a JSON string ({err}).") from None
    for coord in ("time", "x"):
        if coord not in ds.coords:
            raise SchemaError(f"result has no '{coord}' coordinate.")
    if np.any(np.diff(ds["time"].values) <= 0):
        raise SchemaError("coordinate 'time' must be strictly increasing.")
    if "z" in ds.coords and "y" not in ds.coords:
        raise SchemaError("result has a 'z' coordinate but no 'y' coordinate.")
    dims = _spatial_dims(1 + ("y" in ds.coords) + ("z" in ds.coords))
    for name, var in ds.variables.items():
        if name not in VARIABLES:
            raise SchemaError(f"variable {name!r} is not part of the partmesh schema.")
        for key in ("units", "long_name"):
            if key not in var.attrs:
                raise SchemaError(f"variable {name!r} has no '{key}' attribute.")
        expected = None
        if name in FIELDS:
            expected = ("time",) + dims
        elif name == "solid":
            expected = dims
        elif name in SERIES_BY_PROBE:
            expected = ("t_probe", "probe")
        elif name in SERIES:
            expected = ("t_probe",)
        if expected is not None and var.dims != expected:
            raise SchemaError(f"variable {name!r} has dims {var.dims}, expected {expected}.")
    if not any(name in ds.data_vars for name in FIELDS + SERIES_BY_PROBE + SERIES):
        raise SchemaError("result holds no field or time series.")
    return ds


def parameters(ds: xr.Dataset) -> dict:
    """The run's full parameter set, decoded from the ``parameters`` attribute."""
    return json.loads(ds.attrs["parameters"])
