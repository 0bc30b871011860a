"""A drag attempt as a row of the run's ``drags`` table."""

from __future__ import annotations

from scratchworld_dist.kinds.drag._plan import DragBody
from scratchworld_dist.results import DragRow
from scratchworld_dist.sweep import JobSpec
from workers.contract import DragAttempt, JobResult


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
