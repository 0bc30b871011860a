"""Finding a benchmark kind by name: the built-in ones and any a plugin package registers.

Kinds are entry points of the ``scratchworld.kinds`` group (pyproject.toml registers the built-in ones), each
naming an instance of ``scratchworld_dist.kinds.base.Kind``, read through the one entry-point registry
(``workers.Registry``) on first use, not at import. Reports show them in the order of the ``rank`` each declares
(a plugin's, which need not declare one, after the built-ins, by name). Every layer of the driver looks kinds up
here, asking for the facet it uses (``job_kind("drag", KindRows)``): this module imports none of them, so a layer
and the kinds built on it never import each other in a circle.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache
from types import MappingProxyType
from typing import ClassVar, TypeVar

from pydantic import BaseModel

from workers import Registry
from workers._registry import PLUGIN_RANK

ENTRY_POINT_GROUP = "scratchworld.kinds"

DEFAULT_KIND = "tasks"
"""The kind of a sweep config without ``benchmark:``, and of older runs no other kind claims."""


class UnknownKindError(ValueError):
    """A benchmark name no installed kind provides, or an installed kind that cannot be loaded."""


class KindTraits:
    """What every layer may read of a kind without calling its code: its names and the data it declares."""

    name: ClassVar[str] = ""
    """The config's ``benchmark:`` value, the rows' ``benchmark`` column and the entry point's name."""

    title: ClassVar[str] = ""
    """How messages name the kind (``task episodes``, ``single-step drag``...)."""

    rank: ClassVar[int] = PLUGIN_RANK
    """Where reports list it among the kinds (the built-ins declare theirs; a plugin's come after, by name)."""

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


def _not_a_kind(name: str, found: object) -> str | None:
    if not isinstance(found, KindTraits):
        return "is not a kind: see scratchworld_dist.kinds.base.Kind"
    return None if found.name == name else f"names a kind called {found.name!r}"


_KINDS: Registry[KindTraits] = Registry(ENTRY_POINT_GROUP, "benchmark", UnknownKindError, _not_a_kind)


@cache
def _registered() -> dict[str, KindTraits]:
    return _KINDS.load_all()


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
