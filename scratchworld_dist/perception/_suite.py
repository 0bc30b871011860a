"""A perception suite: the items that loaded (and the views ours were made of), and a one-line problem for
everything that did not."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import TaskNotFoundError
from scratchworld_dist.perception._item import PerceptionItem, PerceptionView
from scratchworld_dist.suites import SuiteProblems

PerceptionSuiteKind = Literal["upstream", "scratchworld_dist"]


class PerceptionProblem(BaseModel):
    """Something in a suite that could not be used, naming its file (and line, in a JSON-lines file)."""

    model_config = ConfigDict(frozen=True)

    path: Path
    message: str
    """One line, naming the field at fault; the item or view is left out."""

    def __str__(self) -> str:
        return f"{self.path}: {self.message}"


class PerceptionSuite(BaseModel):
    """The items found in one folder, in suite order; screenshot and project paths are absolute."""

    model_config = ConfigDict(frozen=True)

    name: str
    kind: PerceptionSuiteKind
    root: Path
    items: tuple[PerceptionItem, ...]
    views: tuple[PerceptionView, ...] = ()
    problems: tuple[PerceptionProblem, ...] = ()

    def item(self, item_id: str) -> PerceptionItem:
        for item in self.items:
            if item.id == item_id:
                return item
        raise TaskNotFoundError(f"no perception item {item_id!r} in suite {self.name} ({self.root})")

    def view(self, view_id: str) -> PerceptionView:
        for view in self.views:
            if view.id == view_id:
                return view
        raise TaskNotFoundError(f"no view {view_id!r} in perception suite {self.name} ({self.root})")

    def raise_for_problems(self) -> None:
        """One ``SuiteError`` listing every problem, for callers that want a clean suite or nothing."""
        problems = SuiteProblems(self.root)
        for problem in self.problems:
            problems.add(problem.path, problem.message)
        problems.raise_if_any()
