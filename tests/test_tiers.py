"""The two tiers of the suite: ``python -m pytest -q`` runs the default tier
(pyproject's ``addopts`` leaves out the tests marked ``full`` and ``slow``),
``-m full`` the costlier tests. The default tier is collected here as that
command collects it (in a subprocess, from the repository root) and must
still touch every method and every scene that the entry points register.

A name is touched by a test when its node id names it as a word (``sod``
in ``test_sod_l1_density_error``, the module ``test_fv_euler``), when a
parameter of the test is that name, or when the test's code uses it: a
string or an identifier in the test function, in the fixtures it requests
and in the helpers and constants of its module that these name (``"sod"``,
``sedov_spherical()``). Tests parametrised over the whole registry
(every scene's defaults in ``test_cases``, every method's settings in
``test_settings``) touch every name by construction, so they are counted
apart: a name that some test of either tier touches on its own must be
touched on its own by a default-tier test too, whatever registry-wide
tests there are."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from importlib.metadata import entry_points
from pathlib import Path

import pytest

import partmesh

ROOT = Path(__file__).resolve().parents[1]
TESTS = ROOT / "tests"

#: run in a fresh interpreter: collect as ``python -m pytest -q`` does and write, for every test selected
#: and every test left out, its node id, markers, parameters and the names its code uses
COLLECT = r'''
import ast, inspect, json, sys, textwrap
from pathlib import Path

import pytest

TESTS = Path(sys.argv[2]).resolve()
trees, known = {}, {}


def module_definitions(module):
    """Module-level functions, classes and assigned names of ``module``, by name."""
    if module is None:
        return {}
    if module.__name__ not in trees:
        definitions = {}
        try:
            tree = ast.parse(inspect.getsource(module))
        except (OSError, TypeError, SyntaxError):
            tree = ast.Module(body=[], type_ignores=[])
        for node in tree.body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                definitions[node.name] = node
            elif isinstance(node, (ast.Assign, ast.AnnAssign)):
                for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                    for name in ast.walk(target):
                        if isinstance(name, ast.Name):
                            definitions[name.id] = node
        trees[module.__name__] = definitions
    return trees[module.__name__]


def body(node):
    """What a definition runs: a function without its decorators (a parameter marked into another tier
    is not this test's), anything else whole."""
    if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
        return [*node.args.defaults, *(d for d in node.args.kw_defaults if d is not None), *node.body]
    return [node]


def code_words(function):
    """Strings and identifiers in ``function``, and in the module-level helpers and constants it names."""
    function = inspect.unwrap(function)
    if function not in known:
        known[function] = frozenset(words_of(function))
    return known[function]


def words_of(function):
    try:
        source = Path(inspect.getsourcefile(function)).resolve()
    except (OSError, TypeError):
        return set()
    if TESTS not in source.parents:
        return set()  # (pytest's own fixtures)
    definitions = module_definitions(inspect.getmodule(function))
    start = definitions.get(function.__name__)
    if start is None or getattr(start, "name", None) != function.__name__:
        try:
            start = ast.parse(textwrap.dedent(inspect.getsource(function))).body[0]
        except (OSError, TypeError, SyntaxError, IndexError):
            return set()
    words, todo, done = set(), [start], set()
    while todo:
        node = todo.pop()
        if id(node) in done:
            continue
        done.add(id(node))
        for part in body(node):
            for n in ast.walk(part):
                if isinstance(n, ast.Constant) and isinstance(n.value, str):
                    words.add(n.value)
                elif isinstance(n, ast.Name):
                    words.add(n.id)
                    if n.id in definitions:
                        todo.append(definitions[n.id])
                elif isinstance(n, ast.Attribute):
                    words.add(n.attr)
    return words


def flat(value):
    """The parameter ``value`` as words: strings as they are, containers item by item."""
    if isinstance(value, str):
        return {value}
    if isinstance(value, dict):
        return set().union(*(flat(k) | flat(v) for k, v in value.items())) if value else set()
    if isinstance(value, (list, tuple, set, frozenset)):
        return set().union(*(flat(v) for v in value)) if value else set()
    return {str(value)}


def record(item):
    callspec = getattr(item, "callspec", None)
    params = set().union(*(flat(v) for v in callspec.params.values())) if callspec and callspec.params else set()
    words = set(code_words(item.function)) if hasattr(item, "function") else set()
    fixtures = getattr(getattr(item, "_fixtureinfo", None), "name2fixturedefs", {})
    for definitions in fixtures.values():
        for definition in definitions:
            words |= code_words(definition.func)
    return {"nodeid": item.nodeid, "function": item.nodeid.split("[")[0],
            "text": f"{Path(str(item.path)).stem} {item.name}", "params": sorted(params),
            "words": sorted(words | params), "markers": sorted({m.name for m in item.iter_markers()})}


class Recorder:
    def __init__(self):
        self.left_out = []
        self.selected = []

    def pytest_deselected(self, items):
        self.left_out.extend(items)

    def pytest_collection_finish(self, session):
        self.selected = list(session.items)


recorder = Recorder()
code = pytest.main(["--collect-only", "-q", "-p", "no:cacheprovider", "-n", "0", str(TESTS)], plugins=[recorder])
Path(sys.argv[1]).write_text(json.dumps({"code": int(code), "selected": [record(i) for i in recorder.selected],
                                         "left_out": [record(i) for i in recorder.left_out]}))
'''


@pytest.fixture(scope="module")
def tiers(tmp_path_factory):
    """The tests ``python -m pytest -q`` runs and those it leaves out, this module's own left aside."""
    out = tmp_path_factory.mktemp("tiers") / "tiers.json"
    env = {k: v for k, v in os.environ.items() if k != "PYTEST_ADDOPTS"}  # (the command as typed, nothing added)
    done = subprocess.run([sys.executable, "-c", COLLECT, str(out), str(TESTS)], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0 and out.exists(), done.stdout[-3000:] + done.stderr[-3000:]
    found = json.loads(out.read_text())
    assert found["code"] == 0, found["code"]
    own = Path(__file__).name
    return {tier: [item for item in found[tier] if not item["nodeid"].startswith(f"tests/{own}::")]
            for tier in ("selected", "left_out")}


def registered(group):
    return sorted({entry.name for entry in entry_points(group=group)})


METHODS = registered("partmesh.methods")
SCENES = registered("partmesh.scenes")


def touches(item, name, names):
    """Whether the test ``item`` touches ``name`` (one of ``names``)."""
    if name in item["words"]:
        return True
    text = item["text"].lower()
    for longer in names:  # sedov in sedov_spherical, sph in wcsph: not that name
        if longer != name and name in longer:
            text = text.replace(longer, " ")
    return re.search(rf"(?<![a-z0-9]){re.escape(name)}(?![a-z0-9])", text) is not None


def registry_wide(items, names):
    """Test functions parametrised over every one of ``names``."""
    params = {}
    for item in items:
        params.setdefault(item["function"], set()).update(item["params"])
    return {function for function, values in params.items() if set(names) <= values}


def test_the_entry_points_are_what_partmesh_lists():
    assert METHODS == partmesh.methods() and len(METHODS) >= 6
    assert SCENES == partmesh.scenes() and len(SCENES) >= 20


def test_the_default_run_leaves_out_exactly_the_full_and_slow_tests(tiers):
    selected, left_out = tiers["selected"], tiers["left_out"]
    assert len(selected) > 500 and len(left_out) > 20
    assert not [i["nodeid"] for i in selected if {"full", "slow"} & set(i["markers"])]
    assert not [i["nodeid"] for i in left_out if not {"full", "slow"} & set(i["markers"])]


@pytest.mark.parametrize("kind", ["method", "scene"])
def test_the_default_run_touches_every_method_and_scene(tiers, kind):
    names = {"method": METHODS, "scene": SCENES}[kind]
    default = tiers["selected"]
    every = default + tiers["left_out"]
    untouched = [name for name in names if not any(touches(item, name, names) for item in default)]
    assert not untouched, f"no default-tier test touches the {kind}s {untouched}"
    wide = registry_wide(every, names)
    own = [item for item in every if item["function"] not in wide]
    own_default = [item for item in default if item["function"] not in wide]
    moved = [name for name in names if any(touches(item, name, names) for item in own)
             and not any(touches(item, name, names) for item in own_default)]
    assert not moved, (f"every test of the {kind}s {moved} of their own is marked full or slow; "
                       "keep one in the default run")
