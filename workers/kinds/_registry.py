"""Finding the job kinds: the ``scratchworld.worker_kinds`` entry points, built-in and from plugins.

The built-in kinds are registered in this package's ``pyproject.toml`` like the built-in agents; an
installed package registers a fourth the same way. Loading a kind imports only its light module
(its spec classes and where its runner is): the runners are imported by the kinds' ``run``.
"""

from __future__ import annotations

from importlib.metadata import entry_points

from pydantic import BaseModel

from workers.kinds._protocol import WorkerKind

ENTRY_POINT_GROUP = "scratchworld.worker_kinds"


class KindRegistryError(Exception):
    """A registered kind that cannot be loaded or contradicts another; the message says which, in one line."""


def worker_kinds() -> dict[str, WorkerKind]:
    """Every registered kind by name, read from the installed entry points (a plugin installed later is seen)."""
    kinds: dict[str, WorkerKind] = {}
    owners: dict[type[BaseModel], str] = {}
    for point in sorted(entry_points(group=ENTRY_POINT_GROUP), key=lambda p: p.name):
        if point.name in kinds:
            continue  # one distribution shadows another of the same name, as Python's path decides
        try:
            kind = point.load()
        except Exception as exc:  # a plugin's import may fail in any way: say how, in one line
            detail = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
            raise KindRegistryError(
                f"job kind {point.name} ({point.value}) cannot be imported: {type(exc).__name__}: {detail}"
            ) from exc
        if getattr(kind, "name", None) != point.name or not callable(getattr(kind, "run", None)):
            raise KindRegistryError(
                f"job kind {point.name} ({point.value}) is not a WorkerKind named {point.name!r}: "
                "see workers.kinds.WorkerKind"
            )
        for spec in kind.specs:
            if spec in owners:
                raise KindRegistryError(
                    f"job kinds {owners[spec]} and {point.name} both claim {spec.__name__}: a spec has one kind"
                )
            owners[spec] = point.name
        kinds[point.name] = kind
    return kinds


def kind_named(name: str, kinds: dict[str, WorkerKind] | None = None) -> WorkerKind:
    """The kind called ``name``; raises ``KindRegistryError`` naming the registered ones."""
    kinds = worker_kinds() if kinds is None else kinds
    if name not in kinds:
        known = ", ".join(sorted(kinds)) or "none"
        raise KindRegistryError(
            f"job kind {name!r} is not registered (registered: {known}; built-in names missing: run ./install.sh again)"
        )
    return kinds[name]


def kind_of(spec: BaseModel, kinds: dict[str, WorkerKind] | None = None) -> WorkerKind | None:
    """The kind that runs ``spec`` by its class (or the nearest registered base class), or None."""
    kinds = worker_kinds() if kinds is None else kinds
    by_spec = {cls: kind for kind in kinds.values() for cls in kind.specs}
    return next((by_spec[cls] for cls in type(spec).__mro__ if cls in by_spec), None)
