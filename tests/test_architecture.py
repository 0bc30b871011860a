"""The layout's rules, read from the code: no import circles, a bounded number of driver folders, files of a size
one can read, and no benchmark named outside its own folder.

Imports are read with ``ast`` (inside functions and under ``TYPE_CHECKING`` too): an edge runs from a file to each
file of this tree it names (``from package import module`` names the package's ``__init__.py`` and the module).
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.conftest import REPO

PACKAGES = ("scratchworld_dist", "workers")
KIND_FOLDERS = (REPO / "scratchworld_dist" / "kinds", REPO / "workers" / "kinds")
BUILT_IN_KINDS = frozenset({"tasks", "drag", "perception", "audit"})
MAX_DRIVER_FOLDERS = 12
MAX_LINES = 500


def product_files() -> list[Path]:
    return sorted(path for package in PACKAGES for path in (REPO / package).rglob("*.py"))


def module_file(module: str) -> Path | None:
    path = REPO.joinpath(*module.split("."))
    if (path / "__init__.py").is_file():
        return path / "__init__.py"
    return path.with_suffix(".py") if path.with_suffix(".py").is_file() else None


def module_name(path: Path) -> str:
    parts = list(path.relative_to(REPO).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports_of(path: Path) -> set[Path]:
    """The files of this tree that ``path`` imports, anywhere in it."""
    own = module_name(path).split(".")
    package = own if path.name == "__init__.py" else own[:-1]
    found: set[Path] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found.update(f for alias in node.names if (f := module_file(alias.name)) is not None)
        elif isinstance(node, ast.ImportFrom):
            base = package[: len(package) - node.level + 1] if node.level else []
            module = ".".join([*base, *([node.module] if node.module else [])])
            if module.split(".")[0] not in PACKAGES:
                continue
            found.update(f for f in [module_file(module)] if f is not None)
            found.update(f for alias in node.names if (f := module_file(f"{module}.{alias.name}")) is not None)
    found.discard(path)
    return found


def circles(graph: dict[Path, set[Path]]) -> list[list[Path]]:
    """The strongly connected components of more than one file (Tarjan's algorithm, iterative)."""
    index: dict[Path, int] = {}
    low: dict[Path, int] = {}
    stack: list[Path] = []
    on_stack: set[Path] = set()
    found: list[list[Path]] = []
    for root in graph:
        if root in index:
            continue
        work: list[tuple[Path, Iterator[Path]]] = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, edges = work[-1]
            step = next(edges, None)
            if step is not None:
                if step not in index:
                    index[step] = low[step] = len(index)
                    stack.append(step)
                    on_stack.add(step)
                    work.append((step, iter(sorted(graph.get(step, ())))))
                elif step in on_stack:
                    low[node] = min(low[node], index[step])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_no_file_imports_itself_through_others() -> None:
    graph = {path: imports_of(path) for path in product_files()}
    found = [[str(path.relative_to(REPO)) for path in circle] for circle in circles(graph)]
    assert found == []


def test_the_circle_finder_finds_a_circle_through_a_package_face(tmp_path: Path) -> None:
    a, b, face = tmp_path / "a.py", tmp_path / "b.py", tmp_path / "__init__.py"
    assert circles({a: {b}, b: {face}, face: {a}, tmp_path / "c.py": {a}}) == [sorted([a, b, face])]


def test_the_driver_has_at_most_twelve_folders() -> None:
    folders = [p.name for p in (REPO / "scratchworld_dist").iterdir() if p.is_dir() and p.name != "__pycache__"]
    assert len(folders) <= MAX_DRIVER_FOLDERS, sorted(folders)


def test_every_file_reads_in_one_sitting() -> None:
    long = {str(p.relative_to(REPO)): n for p in product_files() if (n := len(p.read_text().splitlines())) > MAX_LINES}
    assert long == {}


def _in_kind_folder(path: Path) -> bool:
    return any(path.is_relative_to(folder / name) for folder in KIND_FOLDERS for name in BUILT_IN_KINDS)


def _names_a_kind(node: ast.expr) -> bool:
    """Whether an expression reads as a kind or a benchmark (``kind``, ``job.benchmark``, ``body.kind``...)."""
    text = ast.unparse(node).lower()
    return "kind" in text or "benchmark" in text


def dispatches_on_a_kind(tree: ast.AST) -> list[str]:
    """Comparisons of a kind with a built-in kind's name, and tables keyed by several built-in kinds' names."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            constant = [s for s in sides if isinstance(s, ast.Constant | ast.Tuple | ast.List | ast.Set)]
            named = [n.value for s in constant for n in ast.walk(s) if isinstance(n, ast.Constant)]
            if BUILT_IN_KINDS.intersection(named) and any(_names_a_kind(s) for s in sides if s not in constant):
                found.append(ast.unparse(node))
        elif isinstance(node, ast.Dict):
            keys = {k.value for k in node.keys if isinstance(k, ast.Constant) and k.value in BUILT_IN_KINDS}
            if len(keys) > 1:
                found.append(ast.unparse(node)[:80])
        elif isinstance(node, ast.Subscript) and ast.unparse(node.value).endswith("Literal"):
            values = {
                n.value for n in ast.walk(node.slice) if isinstance(n, ast.Constant) and n.value in BUILT_IN_KINDS
            }
            if len(values) > 1:
                found.append(ast.unparse(node))
    return found


def test_no_benchmark_is_named_outside_its_folder() -> None:
    found = {
        str(path.relative_to(REPO)): hits
        for path in product_files()
        if not _in_kind_folder(path) and (hits := dispatches_on_a_kind(ast.parse(path.read_text())))
    }
    assert found == {}


@pytest.mark.parametrize(
    ("code", "dispatches"),
    [
        ("if job.benchmark == 'drag': pass", True),
        ("ok = kind.name in ('perception', 'x')", True),
        ("GROUPS = {'tasks': 1, 'drag': 2}", True),
        ("AgentKind = Literal['tasks', 'drag']", True),
        ("if root.name == 'tasks': pass", False),  # a folder of upstream's layout, not a kind
        ("gesture: Literal['point', 'drag']", False),
    ],
)
def test_the_dispatch_finder_tells_dispatch_from_a_word(code: str, dispatches: bool) -> None:
    assert bool(dispatches_on_a_kind(ast.parse(code))) is dispatches
