"""Entry-point registries: how the driver's job kinds, the worker's job kinds and each kind's agents are found.

Each is an entry-point group: the built-in ones are registered in this package's metadata and a plugin's in its
own, so a new kind or agent edits no shared file (no union, table or order list). One loader serves all three,
so they agree on what a plugin that fails to import looks like (one line naming its entry point), on which of two
entry points of one name counts (the first on Python's path, as an import would), and on order. Both sides use
it: it is here, in the package the driver already imports (see ``workers._lazy`` for the same reason).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from importlib.metadata import EntryPoint, entry_points
from typing import Generic, TypeVar, cast

T = TypeVar("T")

PLUGIN_RANK = 1_000
"""The rank of an object that declares none: after every built-in one (which declare theirs), among plugins by name."""

Check = Callable[[str, object], str | None]
"""Why an object loaded under an entry point's name cannot serve as one of the group's (None: it can), said
after the entry point (``is not a class: see ...``)."""


def rank_of(found: object) -> int:
    """Where ``found`` comes in its group's order: its ``rank`` attribute, or after the built-ins."""
    rank = getattr(found, "rank", PLUGIN_RANK)
    return rank if isinstance(rank, int) else PLUGIN_RANK


def one_line(exc: BaseException, limit: int = 300) -> str:
    """``Type: message`` on one line: a plugin's import may fail in any way, and a message must stay readable."""
    text = " ".join(str(exc).split()) or "no message"
    return f"{type(exc).__name__}: {text[:limit]}"


@dataclass(frozen=True)
class Registry(Generic[T]):
    """One entry-point group, read on each call (a plugin installed later is seen)."""

    group: str
    what: str
    """How messages name an entry (``benchmark``, ``job kind``, ``agent``)."""

    error: type[Exception]
    """What a broken entry raises (the registry's own error class, so callers catch what they always caught)."""

    check: Check
    """The caller's test of a loaded object (its name, its methods...)."""

    def points(self) -> dict[str, EntryPoint]:
        """The group's entry points by name, not loaded; of two of one name, the first on Python's path."""
        found: dict[str, EntryPoint] = {}
        for point in entry_points(group=self.group):
            found.setdefault(point.name, point)
        return found

    def names(self) -> list[str]:
        """The registered names, sorted, without importing anything."""
        return sorted(self.points())

    def load(self, point: EntryPoint) -> T:
        """The object ``point`` names, checked; ``error`` says in one line which entry point failed and how."""
        try:
            found = point.load()
        except Exception as exc:  # a plugin's import may fail in any way: say which and how, in one line
            raise self.error(f"{self.what} {point.name} ({point.value}) cannot be imported: {one_line(exc)}") from exc
        problem = self.check(point.name, found)
        if problem is not None:
            raise self.error(f"{self.what} {point.name} ({point.value}) {problem}")
        return cast(T, found)

    def load_all(self) -> dict[str, T]:
        """Every entry loaded and checked, by name: the built-ins first by the rank each declares, then plugins
        by name."""
        loaded = {name: self.load(point) for name, point in self.points().items()}
        return dict(sorted(loaded.items(), key=lambda item: (rank_of(item[1]), item[0])))
