"""Names of a package that load their module when first used (PEP 562).

A package holds its table ``_LAZY`` (name -> ``"module:attribute"``, or
``"module"`` for a module) and takes its ``__getattr__`` and ``__dir__``
from :func:`lazy_names`; ``tests/test_layers.py`` reads the tables as the
package's imports and lists why each module waits.
"""

import importlib


def lazy_names(package: str, table: dict[str, str], namespace: dict):
    """``(__getattr__, __dir__)`` of ``package`` whose ``namespace``
    (its ``globals()``) gains a name of ``table`` when the name is first
    used, imported then and kept."""

    def __getattr__(name: str):
        if name not in table:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module, _, attribute = table[name].partition(":")
        value = importlib.import_module(module)
        if attribute:
            value = getattr(value, attribute)
        namespace[name] = value  # (looked up once)
        return value

    def __dir__() -> list[str]:
        return sorted({*namespace, *table})

    return __getattr__, __dir__
