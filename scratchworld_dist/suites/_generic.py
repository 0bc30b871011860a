"""What every benchmark's suite is: named items found in one folder, and the problems met finding them."""

from __future__ import annotations

from pathlib import Path
from typing import Generic, Literal, Protocol, TypeVar

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.suites._problems import SuiteProblem, raise_problems

SuiteKind = Literal["scratchworld_dist", "upstream"]
"""Our own format, or a clone of the upstream ScratchWorld repository read in place."""

ItemT = TypeVar("ItemT", bound=BaseModel)
SuiteT_co = TypeVar("SuiteT_co", bound="BaseSuite", covariant=True)


class BaseSuite(BaseModel, Generic[ItemT]):
    """A suite of any benchmark; each benchmark subclasses ``BaseSuite[ItsItem]`` with its own look-ups.

    A suite of tasks raises on any problem, so its ``problems`` are empty; drag and perception suites
    keep going and list here what they left out.
    """

    model_config = ConfigDict(frozen=True)

    name: str
    kind: SuiteKind
    root: Path
    items: tuple[ItemT, ...]
    problems: tuple[SuiteProblem, ...] = ()

    def left_out(self, item_id: str) -> str:
        """Why the item ``item_id`` is not among the items (its problems, each naming its file), or ""."""
        return "; ".join(str(p) for p in self.problems if p.item_id == item_id and p.effect == "skipped")

    def raise_for_problems(self) -> None:
        """One ``SuiteError`` listing every problem, for callers that want a clean suite or nothing."""
        raise_problems(self.root, self.problems)


class SuiteLoader(Protocol[SuiteT_co]):
    """Reads one layout: says whether a folder is in it, and loads it."""

    kind: SuiteKind

    @staticmethod
    def handles(root: Path) -> bool: ...

    def load(self, root: Path) -> SuiteT_co: ...
