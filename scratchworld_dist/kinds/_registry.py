"""Finding a job kind by name: the built-in benchmarks and any a plugin package registers.

Kinds are entry points of the ``scratchworld.kinds`` group (pyproject.toml registers the three built-in
ones), each naming an object that follows ``JobKind``. They are loaded on first use, not at import, so
the modules the core imports never import a kind's code, and a kind's code may import the core.
"""

from __future__ import annotations

from functools import cache
from importlib.metadata import entry_points
from pathlib import Path

from scratchworld_dist.kinds._protocol import JobKind

ENTRY_POINT_GROUP = "scratchworld.kinds"

DEFAULT_KIND = "tasks"
"""The kind of a sweep config without ``benchmark:``, and of older runs no other kind claims."""

BUILT_IN_ORDER = ("tasks", "drag", "perception", "audit")
"""The order reports show the built-in kinds in; a plugin's kinds follow, by name."""


class UnknownKindError(ValueError):
    """A benchmark name no installed kind provides."""


@cache
def _registered() -> dict[str, JobKind]:
    found: dict[str, JobKind] = {}
    for point in entry_points(group=ENTRY_POINT_GROUP):
        try:
            kind = point.load()
        except Exception as exc:  # a plugin's import may fail in any way: say which and how, in one line
            detail = " ".join(str(exc).split()) or type(exc).__name__
            raise UnknownKindError(f"benchmark {point.name} ({point.value}) cannot be imported: {detail}") from exc
        if getattr(kind, "name", None) != point.name:
            raise UnknownKindError(f"entry point {point.name} ({point.value}) names a kind called {kind.name!r}")
        found[point.name] = kind
    order = {name: index for index, name in enumerate(BUILT_IN_ORDER)}
    return dict(sorted(found.items(), key=lambda item: (order.get(item[0], len(order)), item[0])))


def kind_names() -> list[str]:
    """The installed kinds' names, built-in ones first."""
    return list(_registered())


def job_kinds() -> list[JobKind]:
    """The installed kinds, in report order."""
    return list(_registered().values())


def job_kind(name: str) -> JobKind:
    """The kind called ``name``; ``UnknownKindError`` names the installed ones."""
    kinds = _registered()
    if name not in kinds:
        known = ", ".join(kinds) or "none (run ./install.sh again)"
        raise UnknownKindError(f"no benchmark {name!r} is installed (installed: {known})")
    return kinds[name]


def kind_of_run(run_dir: Path) -> JobKind:
    """The kind a run directory holds: as its rows name it; in a run without rows of schema 4 or later, the
    first kind that claims it (``holds``: by its own tables, or its manifest), the default kind last."""
    from scratchworld_dist._errors import RunDirError
    from scratchworld_dist.results import RunStore

    column = RunStore(run_dir).read_table("jobs", columns=["benchmark"]).column("benchmark")
    named = sorted({name for name in column.to_pylist() if name is not None})
    if len(named) > 1:
        raise RunDirError(f"{run_dir}: holds jobs of several benchmarks ({', '.join(named)}); a run holds one")
    if named:
        try:
            return job_kind(named[0])
        except UnknownKindError as exc:
            raise RunDirError(f"{run_dir}: {exc}") from None
    default = job_kind(DEFAULT_KIND)
    return next((kind for kind in job_kinds() if kind is not default and kind.holds(run_dir)), default)
