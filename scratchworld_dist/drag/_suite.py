"""A drag suite: the tasks that loaded, and a one-line problem for everything that did not map."""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import TaskNotFoundError
from scratchworld_dist.drag._task import DragTask
from scratchworld_dist.suites import SuiteKind, SuiteProblems
from workers.contract import DragType

ProblemEffect = Literal["skipped", "no_view", "corrected"]
"""``skipped``: the task is not in the suite; ``no_view``: it is, with ``view`` None;
``corrected``: it is, with an upstream label replaced by what its project says."""


class DragProblem(BaseModel):
    """Something in a suite that could not be used as it is, naming the file it is in."""

    model_config = ConfigDict(frozen=True)

    path: Path
    message: str
    """One line, naming the field at fault."""

    task_id: str | None = None
    effect: ProblemEffect = "skipped"

    def __str__(self) -> str:
        return f"{self.path}: {self.message}"


class DragSuite(BaseModel):
    """The drag tasks found in one folder, in a stable order (type, then id)."""

    model_config = ConfigDict(frozen=True)

    name: str
    kind: SuiteKind
    root: Path
    tasks: tuple[DragTask, ...]
    problems: tuple[DragProblem, ...] = ()

    def task(self, task_id: str) -> DragTask:
        for task in self.tasks:
            if task.id == task_id:
                return task
        raise TaskNotFoundError(f"no drag task {task_id!r} in suite {self.name} ({self.root})")

    def of_type(self, drag_type: DragType) -> tuple[DragTask, ...]:
        return tuple(t for t in self.tasks if t.type == drag_type)

    @property
    def ready(self) -> tuple[DragTask, ...]:
        """The tasks that can be set up: those with a view."""
        return tuple(t for t in self.tasks if t.view is not None)

    def one_per_kind(self) -> tuple[DragTask, ...]:
        """The first ready task of each (connection kind, source kind), in that order: a sample of every case."""
        first: dict[tuple[str, str], DragTask] = {}
        for task in self.ready:
            first.setdefault((task.connection.kind, task.source.kind), task)
        return tuple(first[key] for key in sorted(first))

    def raise_for_problems(self) -> None:
        """One ``SuiteError`` listing every problem, for callers that want a clean suite or nothing."""
        problems = SuiteProblems(self.root)
        for problem in self.problems:
            problems.add(problem.path, problem.message)
        problems.raise_if_any()


def sort_drag_tasks(tasks: list[DragTask]) -> tuple[DragTask, ...]:
    return tuple(sorted(tasks, key=lambda t: (t.type, t.id)))


def problems_from(reader: SuiteProblems, task_id: str | None, effect: ProblemEffect = "skipped") -> list[DragProblem]:
    """What ``reader`` recorded while reading a task's files, as problems of that task."""
    return [DragProblem(path=path, message=message, task_id=task_id, effect=effect) for path, message in reader.items]
