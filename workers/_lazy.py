"""Public names a package exports without importing them yet: its browser-stack parts (a real editor, a runner,
a web server) are reached by their package's name, while importing the package stays light
(tests/test_import_weight.py).

A package lists them once, as ``{module: names}``, and sets ``__getattr__ = workers.lazy_exports(__name__, ...)``;
``from package import name`` then imports the module on first use (PEP 562). It also imports them under
``typing.TYPE_CHECKING``, so that readers and editors see where each name comes from (both through module
names, so that neither is taken for a public name of the package). Both sides use it: it is here,
in the package the driver already imports, rather than copied into each.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping


def lazy_exports(package: str, modules: Mapping[str, tuple[str, ...]]) -> Callable[[str], object]:
    """A module ``__getattr__`` for ``package`` that imports each name of ``modules`` (keyed by the module's
    name relative to the package, ``"._make"``) on first use and keeps it in the package from then on."""
    owners = {name: module for module, names in modules.items() for name in names}

    def attribute(name: str) -> object:
        module = owners.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)
        return value

    return attribute
