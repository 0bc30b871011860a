"""The single-step drag kind (``benchmark: drag``): planning, rows and report of one drag per job.

Its names are imported on first use (``workers.lazy_exports``): the command line imports its command modules,
inside this package, without loading the kind."""

import typing

import workers

if typing.TYPE_CHECKING:
    from scratchworld_dist.kinds.drag._kind import DRAG, DragKind
    from scratchworld_dist.kinds.drag._plan import (
        DragBody,
        DragContent,
        DragTaskInfo,
        drag_job_id,
        plan_drag_jobs,
        read_drag_task,
    )
    from scratchworld_dist.kinds.drag._rows import DragRow

__getattr__ = workers.lazy_exports(
    __name__,
    {
        "._kind": (
            "DRAG",
            "DragKind",
        ),
        "._plan": (
            "DragBody",
            "DragContent",
            "DragTaskInfo",
            "drag_job_id",
            "plan_drag_jobs",
            "read_drag_task",
        ),
        "._rows": ("DragRow",),
    },
)

__all__ = [
    "DRAG",
    "DragBody",
    "DragContent",
    "DragKind",
    "DragRow",
    "DragTaskInfo",
    "drag_job_id",
    "plan_drag_jobs",
    "read_drag_task",
]
