"""A drag suite: the tasks that loaded, and a one-line problem for everything that did not map."""

from __future__ import annotations

from scratchworld_dist._errors import TaskNotFoundError
from scratchworld_dist.kinds.drag.items._task import DragTask
from scratchworld_dist.suites import BaseSuite
from workers.kinds.drag import DragType


class DragSuite(BaseSuite[DragTask]):
    """The drag tasks found in one folder, in a stable order (type, then id); a task that could not be
    used is left out, or kept without a view, with a problem saying which (``SuiteProblem.effect``)."""

    @property
    def tasks(self) -> tuple[DragTask, ...]:
        return self.items

    def task(self, task_id: str) -> DragTask:
        for task in self.items:
            if task.id == task_id:
                return task
        if why := self.left_out(task_id):
            raise TaskNotFoundError(f"drag task {task_id!r} of suite {self.name} was left out: {why}")
        raise TaskNotFoundError(f"no drag task {task_id!r} in suite {self.name} ({self.root})")

    def of_type(self, drag_type: DragType) -> tuple[DragTask, ...]:
        return tuple(t for t in self.items if t.type == drag_type)

    @property
    def ready(self) -> tuple[DragTask, ...]:
        """The tasks that can be set up: those with a view."""
        return tuple(t for t in self.items if t.view is not None)

    def one_per_kind(self) -> tuple[DragTask, ...]:
        """The first ready task of each (connection kind, source kind), in that order: a sample of every case."""
        first: dict[tuple[str, str], DragTask] = {}
        for task in self.ready:
            first.setdefault((task.connection.kind, task.source.kind), task)
        return tuple(first[key] for key in sorted(first))


def sort_drag_tasks(tasks: list[DragTask]) -> tuple[DragTask, ...]:
    return tuple(sorted(tasks, key=lambda t: (t.type, t.id)))
