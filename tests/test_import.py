"""Importing partmesh changes nothing outside it (SPEC §1): JAX's precision
and compilation cache, matplotlib's backend and the working folder are as
the user left them, and no process (git) is started; what a run needs is
set when the run starts. And it is light: ``import partmesh`` and the
command line's parser load none of the heavy libraries, which come with
the first use of a name that needs them (``partmesh.__getattr__``), while
every public name stays where it was. Checked in a fresh interpreter, since
the test session itself configures JAX (conftest.py) and has loaded
everything."""

import json
import subprocess
import sys

import pytest

CHECK = r"""
import json, os, pkgutil, subprocess, importlib
import jax, matplotlib

def settings():
    return {"x64": bool(jax.config.jax_enable_x64), "cache": jax.config.jax_compilation_cache_dir,
            "backend": repr(dict.__getitem__(matplotlib.rcParams, "backend")), "cwd": os.getcwd()}

before = settings()
started = []
def refuse(*args, **kwargs):
    started.append(args[0] if args else kwargs.get("args"))
    raise RuntimeError("an import started a process")
subprocess.Popen.__init__ = refuse

import partmesh
modules = [m.name for m in pkgutil.walk_packages(partmesh.__path__, "partmesh.")]
for name in ("partmesh.cases", "partmesh.compare", "partmesh.gridref", "partmesh.particle", "partmesh.hybrid"):
    package = importlib.import_module(name)
    modules += [m.name for m in pkgutil.walk_packages(package.__path__, name + ".")]
for name in modules:
    if name != "partmesh.__main__":
        importlib.import_module(name)
print(json.dumps({"before": before, "after": settings(), "started": [str(s) for s in started],
                  "modules": len(modules)}))
"""


def test_importing_every_module_leaves_jax_matplotlib_and_the_folder_alone(tmp_path):
    out = subprocess.run([sys.executable, "-c", CHECK], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    found = json.loads(out.stdout.strip().splitlines()[-1])
    assert found["modules"] > 80  # (every module of the six packages was imported)
    assert found["after"] == found["before"]
    assert found["started"] == []


#: libraries that ``import partmesh`` does not load (xarray brings pandas; jax and numba load when a method runs)
HEAVY = ("matplotlib", "scipy", "pandas", "xarray", "numpy", "jax", "numba", "netCDF4", "tqdm",
         "distributed", "dask")
#: the namespace of partmesh as it was when every name was imported eagerly
NAMES = ["InputError", "Method", "Scene", "SchemaError", "SolverFailed", "Unsupported", "WaterScene", "__version__",
         "blast_study", "cases", "cluster", "compare", "dispatch", "ensembles", "method", "methods", "open_sweep",
         "read", "registry", "report", "reporting", "run", "scene", "scene_parameters", "scenes", "study",
         "study_ladder", "sweep", "sweeps", "validate", "version", "write"]

LIGHT = r"""
import json, sys
HEAVY = %r
import partmesh
after_import = sorted(m for m in sys.modules if m.split(".")[0] in HEAVY)
import partmesh.cli
partmesh.cli.parser().format_help()
after_parser = sorted(m for m in sys.modules if m.split(".")[0] in HEAVY)
listed = dir(partmesh)
found = {name: type(getattr(partmesh, name)).__name__ for name in %r}
import partmesh.compare
compare = {name: type(getattr(partmesh.compare, name)).__name__ for name in partmesh.compare.__all__}
print(json.dumps({"after_import": after_import, "after_parser": after_parser, "dir": listed, "found": found,
                  "all": partmesh.__all__, "compare": compare, "compare_dir": dir(partmesh.compare)}))
"""


def test_import_and_the_command_line_parser_load_no_heavy_library_and_every_name_resolves(tmp_path):
    out = subprocess.run([sys.executable, "-c", LIGHT % (HEAVY, NAMES)], cwd=tmp_path, capture_output=True, text=True,
                         timeout=600, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    found = json.loads(out.stdout.strip().splitlines()[-1])
    assert found["after_import"] == []
    assert found["after_parser"] == []
    assert set(NAMES) <= set(found["dir"])
    assert set(found["all"]) <= set(NAMES)
    assert sorted(found["found"]) == sorted(NAMES)  # (each resolved, to a value of its kind:)
    kinds = {name: "module" for name in ("blast_study", "cases", "cluster", "compare", "dispatch", "ensembles",
                                         "registry", "reporting", "sweeps")}
    kinds.update({name: "type" for name in NAMES if name[0].isupper()}, __version__="str")
    assert found["found"] == {name: kinds.get(name, "function") for name in NAMES}
    assert sorted(found["compare"]) == ["SchemaError", "read", "result", "validate", "write"]
    assert set(found["compare"]) <= set(found["compare_dir"])


def test_lazy_names_are_the_objects_they_stand_for():
    import partmesh
    from partmesh import blast_study, dispatch, sweeps
    from partmesh.cases import registry, scene
    from partmesh.compare import io, schema

    assert partmesh.run is dispatch.run
    assert partmesh.study is blast_study.run_study and partmesh.study_ladder is blast_study.run_sensitivity
    assert (partmesh.scene, partmesh.scenes, partmesh.scene_parameters, partmesh.method) == (
        registry.get, registry.names, registry.defaults, registry.method)
    assert partmesh.sweep is sweeps.sweep and partmesh.open_sweep is sweeps.open_sweep
    assert (partmesh.read, partmesh.write, partmesh.validate) == (io.read, io.write, schema.validate)
    assert partmesh.Scene is scene.Scene and partmesh.SchemaError is schema.SchemaError
    assert partmesh.__version__ == schema.version()
    assert partmesh.methods() == sorted(registry.methods())
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        partmesh.nothing  # noqa: B018
    with pytest.raises(ImportError):
        from partmesh import nothing  # noqa: F401
