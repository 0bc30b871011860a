"""The single-step drag kind (``benchmark: drag``): planning, rows and report of one drag per job."""

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
