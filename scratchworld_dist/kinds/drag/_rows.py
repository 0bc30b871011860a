"""The drag kind's own table, ``drags``: one row per attempt."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.kinds.drag._plan import DragBody
from scratchworld_dist.sweep import JobSpec
from workers.contract import JobResult
from workers.kinds.drag import DragAttempt


class DragRow(BaseModel):
    """What one drag attempt predicted and how far it was from the exact regions (a row of ``drags/``).

    Points are page px as performed; ``end_*`` distances are for the release translated by
    ``fixed_start - start`` (a press elsewhere in the block moves the block's grip by as much).
    """

    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int
    task_id: str
    drag_type: str
    """T1 (stacking) or T2 (nesting)."""

    connection: str
    """The expected connection kind: parent, next, substack_1, substack_2 or input."""

    source: str
    """Where the dragged block comes from: canvas or flyout."""

    setting: str
    model: str
    agent: str
    seed: int
    parse: str
    """How the reply was read: ok, no_answer, unparsed, bad_index or out_of_screen."""

    start_x: float | None
    start_y: float | None
    end_x: float | None
    end_y: float | None
    start_in_region: bool | None
    start_error_px: float | None
    end_in_region: bool | None
    end_error_px: float | None
    connected: bool
    observed: str
    fixed_start_x: int
    fixed_start_y: int
    """The press the end region is for (a deepest pixel of the start region)."""

    gt_start_x: int | None
    gt_start_y: int | None
    start_area: int
    end_area: int
    regions_json: str
    """The exact regions, ``{"start": {"rows": [[y, x_first, x_last], ...]}, "fixed_start": [x, y], "end": {...}}``
    (``DragRegions.model_validate_json`` reads it back): any other distance or metric is a query away."""
    reply: str | None
    """The model's raw reply (null for scripted agents)."""

    annotated: str | None
    """The annotated screenshot (prediction and regions), relative to the run directory."""


def drag_row(job: JobSpec, result: JobResult, annotated: str | None) -> DragRow:
    drag, body = result.detail, job.body
    if not isinstance(drag, DragAttempt) or not isinstance(body, DragBody):
        raise ValueError(f"job {job.job_id} is not a drag job")
    start, end, regions, marked = drag.start, drag.end, drag.regions, drag.gt_start
    return DragRow(
        job_id=job.job_id,
        attempt=result.attempt,
        task_id=job.task_id,
        drag_type=body.task.type,
        connection=body.task.connection,
        source=body.task.source,
        setting=drag.setting,
        model=job.model_name,
        agent=job.agent_label,
        seed=job.seed,
        parse=drag.parse,
        start_x=start[0] if start else None,
        start_y=start[1] if start else None,
        end_x=end[0] if end else None,
        end_y=end[1] if end else None,
        start_in_region=drag.start_in_region,
        start_error_px=drag.start_error_px,
        end_in_region=drag.end_in_region,
        end_error_px=drag.end_error_px,
        connected=drag.connected,
        observed=drag.observed,
        fixed_start_x=regions.fixed_start[0],
        fixed_start_y=regions.fixed_start[1],
        gt_start_x=marked[0] if marked else None,
        gt_start_y=marked[1] if marked else None,
        start_area=regions.start.area,
        end_area=regions.end.area,
        regions_json=regions.model_dump_json(exclude={"computed_s"}),
        reply=next((step.reply for step in result.steps if step.reply is not None), None),
        annotated=annotated,
    )
