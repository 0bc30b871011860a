"""The report core and the viewer know no kind: nothing in ``scratchworld_dist.reports`` or
``scratchworld_dist.viewer`` imports a kind's folder (``scratchworld_dist.kinds.tasks``...), at module level or in a
function. They find kinds through the registry (``scratchworld_dist.kinds``) and the facets each defines, which a
kind implements. And the report core's surface is complete and sorted."""

from __future__ import annotations

import ast
import importlib
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import REPO

CORE = ("scratchworld_dist/reports", "scratchworld_dist/viewer")
KINDS = "scratchworld_dist.kinds"


def kind_folders() -> set[str]:
    """The kinds' folders: every package under ``scratchworld_dist/kinds``."""
    return {path.parent.name for path in (REPO / "scratchworld_dist" / "kinds").glob("*/__init__.py")}


def imported(source: str, package: str) -> Iterator[tuple[int, str]]:
    """Every module a module of ``package`` names in an import anywhere in ``source`` (relative imports resolved,
    ``importlib.import_module("...")`` too), with its line; a ``from`` import names its module and each of its names
    (any may be a submodule)."""
    parts = package.split(".")
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            yield from ((node.lineno, alias.name) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = parts[: len(parts) - node.level + 1] if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            yield node.lineno, module
            yield from ((node.lineno, f"{module}.{alias.name}") for alias in node.names)
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", getattr(node.func, "id", None)) in (
            "import_module",
            "__import__",
        ):
            yield from ((node.lineno, arg.value) for arg in node.args[:1] if isinstance(arg, ast.Constant))


def kinds_imported(path: Path) -> list[str]:
    """What the module at ``path`` imports of a kind's folder, as ``line N: module``."""
    parts = list(path.relative_to(REPO).with_suffix("").parts)
    package = ".".join(parts[:-1])  # a package's __init__ and its modules resolve relative imports alike
    folders = kind_folders()
    return [
        f"line {line}: {name}"
        for line, name in imported(path.read_text(), package)
        if name.startswith(f"{KINDS}.") and name.split(".")[2] in folders
    ]


def core_files() -> list[Path]:
    return sorted(path for folder in CORE for path in (REPO / folder).rglob("*.py"))


def test_the_scan_sees_imports_in_functions_relative_and_by_name() -> None:
    source = (
        "import scratchworld_dist.kinds\n"
        "def page():\n"
        "    from scratchworld_dist.kinds import tasks, job_kind\n"
        "    from ..kinds.drag import table\n"
        "    importlib.import_module('scratchworld_dist.kinds.audit._panel')\n"
    )
    names = {name for _, name in imported(source, "scratchworld_dist.viewer")}
    assert {f"{KINDS}.tasks", f"{KINDS}.drag.table", f"{KINDS}.audit._panel"} <= names
    assert {"scratchworld_dist.kinds", "scratchworld_dist.kinds.job_kind"} <= names  # the registry: allowed


@pytest.mark.parametrize("path", core_files(), ids=lambda p: str(p.relative_to(REPO)))
def test_a_core_module_imports_no_kind(path: Path) -> None:
    assert {"tasks", "drag", "perception", "audit"} <= kind_folders()
    assert not kinds_imported(path), f"{path.relative_to(REPO)} imports a kind's folder"


def test_public_surface_is_complete_and_sorted() -> None:
    module = importlib.import_module("scratchworld_dist.reports")
    for member in module.__all__:
        getattr(module, member)  # a lazy export (draw_plots, which imports matplotlib) joins vars here
    public = [m for m, v in vars(module).items() if not m.startswith("_") and type(v).__name__ != "module"]
    assert sorted(module.__all__) == sorted(public)
    assert list(module.__all__) == sorted(module.__all__, key=lambda s: (not s.isupper(), not s[0].isupper(), s))
