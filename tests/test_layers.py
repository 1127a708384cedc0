"""The package's layers point one way (SPEC §1): compare ← cases ← gridref,
particle ← hybrid ← partmesh, with no import cycle, no import hidden in a
function body, and every folder of the source tree installed under the one
namespace ``partmesh``. Read from the source with ``ast``: nothing is
imported to check it.

Two kinds of import are put off for their weight, and only where listed
here with the reason: imports inside functions (``LAZY``), and the modules
a package's ``__init__`` loads when one of its names is first used (its
PEP 562 table ``_LAZY``; ``ON_FIRST_USE``), which count as imports of that
package for the layers and the cycle check."""

import ast
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: folder -> (its dotted name under partmesh, its layer)
FOLDERS = {"compare": ("partmesh.compare", 0), "cases": ("partmesh.cases", 1), "gridref": ("partmesh.gridref", 2),
           "particle": ("partmesh.particle", 2), "hybrid": ("partmesh.hybrid", 3), "partmesh": ("partmesh", 4)}
#: imports that stay inside functions, each for a reason of its own
LAZY = {
    "dask": "xarray imports dask.array on the first result it builds (about 0.4 s): a grid method loads it while "
            "XLA compiles its loop, in another thread",
    "distributed": "Dask's scheduler and workers start only for sweeps, ensembles and studies (about 1 s to import)",
    "numba": "a Dask worker sets its numba threads before the run's kernels load",
    "scipy": "the Sedov energy integral's quadrature: the exact solutions a run's scene loads stay without SciPy "
             "(about 0.5 s); the k-d tree of a body's image points with no fluid around them: an fv run without "
             "such points stays without scipy.spatial (about 0.15 s)",
    "jax": "bench reads the device JAX runs on, and JAX loads only when a grid method runs",
}
#: package -> {module its ``_LAZY`` table loads on first use: why not at ``import``} (see test_import.py)
ON_FIRST_USE = {
    "partmesh": {
        "partmesh.cases.method": "the method contract and its settings: dataclasses and typing (about 35 ms)",
        "partmesh.cases.scene": "NumPy (about 0.15 s), for the scene types",
        "partmesh.cases.registry": "reads the schema's entry-point group, and so xarray and pandas (about 0.5 s)",
        "partmesh.compare.schema": "xarray and pandas (about 0.5 s)",
        "partmesh.compare.io": "xarray and pandas, netCDF on first use",
        "partmesh.dispatch": "xarray (tiling of results), the registry",
        "partmesh.reporting": "pandas, SciPy (exact solutions) and matplotlib (figures): about 1.5 s",
        "partmesh.sweeps": "xarray and tqdm; Dask when a sweep starts",
        "partmesh.blast_study": "pandas, SciPy and matplotlib, for the blast scenes and their figures (about 2 s)",
        "partmesh.bench": "the methods and metrics (SciPy), for the bench command only",
        "partmesh.cluster": "the checkpoint machinery and the schema (xarray), for runs on Dask",
        "partmesh.demo": "reports (matplotlib), for the demo command only",
        "partmesh.ensembles": "the registry and the checkpoint machinery (xarray), for runs on Dask",
        "partmesh.warmup": "multiprocessing, for compiling methods side by side",
    },
    "partmesh.compare.exact": {
        "partmesh.compare.exact.kingery_bulmash": "the surface-burst fits, for the blast scenes' references",
        "partmesh.compare.exact.detonation": "SciPy (quadrature, root finding), for the detonation's Taylor wave",
        "partmesh.compare.exact.shocks": "SciPy (root finding), for the shock tube's and blast inflow's states",
        "partmesh.compare.exact.stoker_ritter": "SciPy (root finding), for the dam-break references",
        "partmesh.compare.exact.water": "SciPy (Bessel functions), for the wave references",
    },
    "partmesh.compare.metrics": {
        "partmesh.compare.metrics.probe_series": "SciPy (root finding), for the probe-series measures",
    },
    "partmesh.compare": {
        "partmesh.compare.schema": "xarray and pandas, which partmesh.compare.checks (InputError) does not need",
        "partmesh.compare.io": "xarray and pandas, netCDF on first use",
    },
}


def _modules() -> dict[str, Path]:
    found = {}
    for folder, (dotted, _) in FOLDERS.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            parts = list(path.relative_to(ROOT / folder).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            found[".".join([dotted, *parts])] = path
    return found


MODULES = _modules()


def _layer(module: str) -> tuple[str, int]:
    """The package a module belongs to and its layer (the top package's own modules are 'partmesh')."""
    for dotted, layer in sorted(FOLDERS.values(), key=lambda v: -len(v[0])):
        if module == dotted or module.startswith(dotted + "."):
            return dotted, layer
    raise KeyError(module)


def _lazy_table(module: str) -> tuple[dict[str, str], int]:
    """A package's PEP 562 table ``_LAZY`` (name -> "module:attribute") and its line; empty if none."""
    path = MODULES[module]
    for node in ast.parse(path.read_text(), str(path)).body:
        if isinstance(node, ast.Assign) and [getattr(t, "id", None) for t in node.targets] == ["_LAZY"]:
            return ast.literal_eval(node.value), node.lineno
    return {}, 0


def _imports(module: str) -> list[tuple[str, bool, int]]:
    """(imported name, whether inside a function, line) of every import of ``module``, the modules
    of its ``_LAZY`` table among them (as imports at module level)."""
    path = MODULES[module]
    tree = ast.parse(path.read_text(), str(path))
    table, table_line = _lazy_table(module)
    in_function = {id(node) for f in ast.walk(tree) if isinstance(f, (ast.FunctionDef, ast.AsyncFunctionDef))
                   for node in ast.walk(f) if isinstance(node, (ast.Import, ast.ImportFrom))}
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            names = [f"{base}.{a.name}" if f"{base}.{a.name}" in MODULES else base for a in node.names]
        else:
            continue
        out += [(name, id(node) in in_function, node.lineno) for name in names]
    out += [(name, False, table_line) for name in sorted({v.partition(":")[0] for v in table.values()})]
    return out


def _graph() -> dict[str, set[str]]:
    return {m: {name for name, _, _ in _imports(m) if name in MODULES} for m in MODULES}


def test_every_package_of_the_tree_is_installed_under_partmesh():
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    packages = {m for m, p in MODULES.items() if p.name == "__init__.py"}
    assert set(config["packages"]) == packages
    assert config["package-dir"] == {dotted: folder for folder, (dotted, _) in FOLDERS.items()}


def test_no_module_imports_from_a_layer_above_or_beside_its_own():
    upward = []
    for module in MODULES:
        package, layer = _layer(module)
        for name, _, line in _imports(module):
            if name.split(".")[0] != "partmesh":
                continue
            target = next((m for m in sorted(MODULES, key=len, reverse=True)
                           if name == m or name.startswith(m + ".")), name)
            target_package, target_layer = _layer(target)
            if target_layer > layer or (target_layer == layer and target_package != package):
                upward.append(f"{module}:{line} imports {name}")
    assert upward == []


def test_the_import_graph_has_no_cycle():
    graph, state, cycles = _graph(), {}, []

    def visit(module, stack):
        state[module] = "open"
        for target in sorted(graph[module]):
            if state.get(target) == "open":
                cycles.append(" -> ".join(stack[stack.index(target):] + [target]))
            elif target not in state:
                visit(target, stack + [target])
        state[module] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])
    assert cycles == []


def test_imports_inside_functions_are_only_the_lazy_heavy_ones():
    hidden = [f"{m}:{line} imports {name}" for m in MODULES for name, inside, line in _imports(m)
              if inside and name.split(".")[0] not in LAZY]
    assert hidden == []


def test_modules_loaded_on_first_use_are_only_the_listed_ones():
    tables = {m: {v.partition(":")[0] for v in _lazy_table(m)[0].values()} for m in MODULES}
    assert {m: t for m, t in tables.items() if t} == {m: set(listed) for m, listed in ON_FIRST_USE.items()}
    for package, table in ON_FIRST_USE.items():
        assert all(reason for reason in table.values()), package
        assert set(table) <= set(MODULES), package  # (a table names modules of the tree)


def test_input_error_has_one_home_per_side_of_the_layers():
    # (defined in compare, the layer every other imports; published for the rest by cases.errors)
    homes = {m: "partmesh.compare.checks" if _layer(m)[1] == 0 else "partmesh.cases.errors" for m in MODULES}
    elsewhere = []
    for module, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if (isinstance(node, ast.ImportFrom) and any(a.name == "InputError" for a in node.names)
                    and node.module != homes[module] and module != "partmesh.cases.errors"):
                elsewhere.append(f"{module}:{node.lineno} imports InputError from {node.module}")
    assert elsewhere == []


def test_the_checker_sees_the_imports_it_judges():
    # (an empty graph would pass every test above)
    graph = _graph()
    assert "partmesh.compare.schema" in graph["partmesh.cases.history"]
    assert "partmesh.cases.march" in graph["partmesh.particle.march"]
    assert {"partmesh.gridref.euler.method", "partmesh.particle.sph.method"} <= set(graph)
    assert {"partmesh.dispatch", "partmesh.blast_study"} <= graph["partmesh"]  # (through its _LAZY table)
    assert _lazy_table("partmesh")[0]["run"] == "partmesh.dispatch:run"
