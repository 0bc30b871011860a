"""Finding the job kinds: the ``scratchworld.worker_kinds`` entry points, built-in and from plugins.

The built-in kinds are registered in this package's ``pyproject.toml`` like the built-in agents; an
installed package registers a fourth the same way, through the one entry-point registry (``workers.Registry``).
Loading a kind imports only its light module (its spec classes and where its runner is): the runners are
imported by the kinds' ``run``.
"""

from __future__ import annotations

from pydantic import BaseModel

from workers import Registry
from workers.kinds._protocol import AgentGroup, WorkerKind

DEFAULT_KIND = "tasks"
"""The kind whose agents a name means when no kind is given: the episode agents (``scratchworld.agents``), the
group plugins have always registered in."""

ENTRY_POINT_GROUP = "scratchworld.worker_kinds"


class KindRegistryError(Exception):
    """A registered kind that cannot be loaded or contradicts another; the message says which, in one line."""


def _not_a_kind(name: str, found: object) -> str | None:
    if getattr(found, "name", None) != name or not callable(getattr(found, "run", None)):
        return f"is not a WorkerKind named {name!r}: see workers.kinds.WorkerKind"
    if not isinstance(agents_of(found), AgentGroup | None):
        return "declares agents that are not an AgentGroup: see workers.kinds.AgentGroup"
    return None


_KINDS: Registry[WorkerKind] = Registry(ENTRY_POINT_GROUP, "job kind", KindRegistryError, _not_a_kind)


def worker_kinds() -> dict[str, WorkerKind]:
    """Every registered kind by name, read from the installed entry points (a plugin installed later is seen)."""
    kinds = _KINDS.load_all()
    owners: dict[type[BaseModel], str] = {}
    for name, kind in kinds.items():
        for spec in kind.specs:
            if spec in owners:
                raise KindRegistryError(
                    f"job kinds {owners[spec]} and {name} both claim {spec.__name__}: a spec has one kind"
                )
            owners[spec] = name
    return kinds


def agents_of(kind: object) -> AgentGroup | None:
    """Where ``kind``'s agents register (None: it runs none, as a plugin kind without ``agents`` does)."""
    return getattr(kind, "agents", None)


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
