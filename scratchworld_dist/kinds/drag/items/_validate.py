"""Validating a drag suite in this editor: every task's exact regions, and the oracle's drag through them.

A task is valid when its view sets up, its regions are not empty, and a real drag from the start
region's deepest pixel to the end region's makes the expected connection. ``drag make`` keeps only
candidates that pass this, and ``scratchworld drag validate`` runs it on any suite (ours, or an
upstream clone's 60), keeping each task's regions (run-length rows) with its verdict.
"""

from __future__ import annotations

import asyncio
from collections.abc import Callable, Sequence

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.kinds.drag.items._task import DragTask
from workers.contract import AgentRef, DragRegions, JobResult
from workers.editor import BrowserConfig, BrowserSession, EditorPool
from workers.kinds.drag import DragAttempt, DragPayload, DragRunner, DragSpec


class DragTaskCheck(BaseModel):
    """One task's validation: the oracle's verdict, why it failed, and the regions it was aimed with."""

    model_config = ConfigDict(frozen=True)

    task_id: str
    type: str
    connection: str
    source: str
    valid: bool
    detail: str
    """What the oracle's drag did (or why there was none), in words."""

    regions: DragRegions | None
    """None when the task could not be set up or its regions are empty."""

    seconds: float


async def oracle_drag(runner: DragRunner, payload: DragPayload) -> JobResult:
    """The oracle's one drag on a task: regions computed in the runner's editor, then a real drag at their centres."""
    spec = DragSpec(
        job_id=f"oracle-{payload.task_id}",
        attempt=1,
        task_id=payload.task_id,
        setting="baseline",
        agent=AgentRef(name="oracle"),
        model=None,
        seed=0,
        timeout_s=120,
    )
    return await runner.run(spec, payload)


def check_of(task: DragTask, result: JobResult) -> DragTaskCheck:
    drag = result.detail if isinstance(result.detail, DragAttempt) else None
    detail = result.error_message or (drag.observed if drag is not None else result.stop_reason)
    return DragTaskCheck(
        task_id=task.id,
        type=task.type,
        connection=task.connection.kind,
        source=task.source.kind,
        valid=result.outcome == "passed",
        detail=detail,
        regions=drag.regions if drag is not None else None,
        seconds=result.timings.total_s,
    )


async def validate_drag_tasks(
    tasks: Sequence[DragTask],
    *,
    editors: int = 1,
    on_checked: Callable[[DragTaskCheck], None] = lambda _: None,
) -> list[DragTaskCheck]:
    """Check ``tasks`` (with a view) in ``editors`` recycled editors at a time, in the order given."""
    queue: asyncio.Queue[int] = asyncio.Queue()
    for index in range(len(tasks)):
        queue.put_nowait(index)
    checks: dict[int, DragTaskCheck] = {}
    async with BrowserSession(BrowserConfig()) as session, EditorPool(session, spare=0) as pool:
        runner = DragRunner(pool)

        async def work() -> None:
            while not queue.empty():
                index = queue.get_nowait()
                task = tasks[index]
                payload = task.payload(task.initial_project.read_bytes())
                checks[index] = check_of(task, await oracle_drag(runner, payload))
                on_checked(checks[index])

        await asyncio.gather(*(work() for _ in range(max(1, editors))))
    return [checks[index] for index in range(len(tasks))]
