"""Entry-point registries: how the driver's job kinds, the worker's job kinds and each kind's agents are found.

Each is an entry-point group: the built-in ones are registered in this package's metadata and a plugin's in its
own, so a new kind or agent edits no shared file (no union, table or order list). One loader serves all three,
so they agree on what a plugin that fails to import looks like (one line naming its entry point), on which of two
entry points of one name counts (the first on Python's path, as an import would), and on order. Both sides use
it: it is here, in the package the driver already imports (see ``workers._lazy`` for the same reason).
"""

from __future__ import annotations

import os
import sys
import threading
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


_PathStamp = tuple[tuple[str, int | None], ...]
_read: dict[str, tuple[_PathStamp, tuple[EntryPoint, ...]]] = {}
_read_lock = threading.Lock()


def _path_stamp() -> _PathStamp:
    """Python's path with each directory's modification time: installing a distribution adds its ``dist-info``
    to a directory on the path (changing its time), a plugin's own directory joins the path."""
    stamp = []
    for entry in sys.path:
        try:
            stamp.append((entry, os.stat(entry or ".").st_mtime_ns))
        except OSError:
            stamp.append((entry, None))
    return tuple(stamp)


def group_entry_points(group: str) -> tuple[EntryPoint, ...]:
    """The entry points of ``group``, read again only when Python's path or a directory on it changed.

    Reading them scans every installed distribution's metadata (25-55 ms on 2 cores), and a worker looks its
    kinds and agents up for every job, several groups each time (py-spy put these scans at 4.5% of a worker's
    samples at 32 episodes in flight)."""
    stamp = _path_stamp()
    with _read_lock:
        known = _read.get(group)
        if known is not None and known[0] == stamp:
            return known[1]
    points = tuple(entry_points(group=group))
    with _read_lock:
        _read[group] = (stamp, points)
    return points


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
    """One entry-point group, read again whenever Python's path changed (a plugin installed later is seen)."""

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
        for point in group_entry_points(self.group):
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
