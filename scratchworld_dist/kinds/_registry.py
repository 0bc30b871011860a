"""Finding a job kind by name: the built-in benchmarks and any a plugin package registers.

Kinds are entry points of the ``scratchworld.kinds`` group (pyproject.toml registers the four built-in ones),
each naming an object that follows ``JobKind``, loaded through the one entry-point registry (``workers.Registry``).
They are loaded on first use, not at import, so the modules the core imports never import a kind's code, and a
kind's code may import the core. Reports show the kinds in the order of the ``rank`` each declares (a plugin's,
which need not declare one, after the built-ins, by name).
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

from scratchworld_dist.kinds._protocol import JobKind
from workers import Registry

ENTRY_POINT_GROUP = "scratchworld.kinds"

DEFAULT_KIND = "tasks"
"""The kind of a sweep config without ``benchmark:``, and of older runs no other kind claims."""


class UnknownKindError(ValueError):
    """A benchmark name no installed kind provides, or an installed kind that cannot be loaded."""


def _misnamed(name: str, found: object) -> str | None:
    called = getattr(found, "name", None)
    return None if called == name else f"names a kind called {called!r}"


_KINDS: Registry[JobKind] = Registry(ENTRY_POINT_GROUP, "benchmark", UnknownKindError, _misnamed)


@cache
def _registered() -> dict[str, JobKind]:
    return _KINDS.load_all()


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
