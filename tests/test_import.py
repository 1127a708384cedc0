"""Importing partmesh changes nothing outside it (SPEC §1): JAX's precision
and compilation cache, matplotlib's backend and the working folder are as
the user left them, and no process (git) is started; what a run needs is
set when the run starts. Checked in a fresh interpreter, since the test
session itself configures JAX (conftest.py)."""

import json
import subprocess
import sys

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
