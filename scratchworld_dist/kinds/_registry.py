"""Finding a benchmark kind by name: the built-in ones and any a plugin package registers.

Kinds are entry points of the ``scratchworld.kinds`` group (pyproject.toml registers the built-in ones), each
naming an instance of ``scratchworld_dist.kinds.base.Kind``. They are loaded on first use, not at import. Every
layer of the driver looks kinds up here, asking for the facet it uses (``job_kind("drag", KindRows)``): this
module imports none of them, so a layer and the kinds built on it never import each other in a circle.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache
from importlib.metadata import entry_points
from types import MappingProxyType
from typing import ClassVar, TypeVar

from pydantic import BaseModel

ENTRY_POINT_GROUP = "scratchworld.kinds"

DEFAULT_KIND = "tasks"
"""The kind of a sweep config without ``benchmark:``, and of older runs no other kind claims."""


class UnknownKindError(ValueError):
    """A benchmark name no installed kind provides, or a registered object that is no kind."""


class KindTraits:
    """What every layer may read of a kind without calling its code: its names and the data it declares."""

    name: ClassVar[str] = ""
    """The config's ``benchmark:`` value, the rows' ``benchmark`` column and the entry point's name."""

    title: ClassVar[str] = ""
    """How messages name the kind (``task episodes``, ``single-step drag``...)."""

    rank: ClassVar[int] = 100
    """Where reports list it among the kinds (built-ins below 100; plugins after them, by name)."""

    needs_browser: ClassVar[bool] = True
    """Whether its jobs open an editor (admission and warm editors count only those that do)."""

    episodes: ClassVar[bool] = False
    """Whether its jobs are agent episodes (steps, a final project, tests): the run plots and the exports
    (leaderboard, upstream submission, ATIF) are made of those."""

    tables: ClassVar[Mapping[str, type[BaseModel]]] = MappingProxyType({})
    """Result tables of its own besides ``jobs``, ``steps`` and ``tests``: folder name and row model (with
    ``job_id`` and ``attempt``; a run holds the tables of its kind)."""

    config_section: ClassVar[type[BaseModel] | None] = None
    """The model of its section of a sweep config (None: it has none). The model may list in a ``former_keys``
    class attribute the top-level keys it took over (they still read there, moved into it with a notice), and in
    ``resume_free`` (pydantic's ``exclude`` form) what may change between sessions of one run."""

    config_key: ClassVar[str | None] = None
    """The key of that section (default: the kind's name, ``drag:``; the task episodes' is ``episodes:``, since
    ``tasks:`` is the selection every kind reads)."""

    @classmethod
    def section_key(cls) -> str:
        return cls.config_key or cls.name


FacetT = TypeVar("FacetT", bound=KindTraits)


@cache
def _registered() -> dict[str, KindTraits]:
    found: dict[str, KindTraits] = {}
    for point in entry_points(group=ENTRY_POINT_GROUP):
        try:
            kind = point.load()
        except Exception as exc:  # a plugin's import may fail in any way: say which and how, in one line
            detail = " ".join(str(exc).split()) or type(exc).__name__
            raise UnknownKindError(f"benchmark {point.name} ({point.value}) cannot be imported: {detail}") from exc
        if not isinstance(kind, KindTraits):
            raise UnknownKindError(
                f"entry point {point.name} ({point.value}) is not a kind: see scratchworld_dist.kinds.base.Kind"
            )
        if kind.name != point.name:
            raise UnknownKindError(f"entry point {point.name} ({point.value}) names a kind called {kind.name!r}")
        found[point.name] = kind
    return dict(sorted(found.items(), key=lambda item: (item[1].rank, item[0])))


def kind_names() -> list[str]:
    """The installed kinds' names, in report order."""
    return list(_registered())


def job_kinds(facet: type[FacetT] = KindTraits) -> list[FacetT]:  # type: ignore[assignment]
    """The installed kinds, in report order, as ``facet`` (each must provide it)."""
    return [_as(kind, facet) for kind in _registered().values()]


def job_kind(name: str, facet: type[FacetT] = KindTraits) -> FacetT:  # type: ignore[assignment]
    """The kind called ``name`` as ``facet``; ``UnknownKindError`` names the installed ones."""
    kinds = _registered()
    if name not in kinds:
        known = ", ".join(kinds) or "none (run ./install.sh again)"
        raise UnknownKindError(f"no benchmark {name!r} is installed (installed: {known})")
    return _as(kinds[name], facet)


def _as(kind: KindTraits, facet: type[FacetT]) -> FacetT:
    if not isinstance(kind, facet):
        raise UnknownKindError(
            f"benchmark {kind.name} ({type(kind).__module__}) lacks {facet.__name__}: "
            "build kinds on scratchworld_dist.kinds.base.Kind"
        )
    return kind
