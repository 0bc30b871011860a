"""Browserless episodes: the scheduler, results and reports exercised without an editor.

Used by ``benchmarks/scheduler.py``, ``benchmarks/chaos.py`` and by cluster smoke tests; a
synthetic episode waits for its duration and reports a verdict decided by the task id, as a real
one would. ``tasks`` limits them to some tasks, so one sweep can mix cheap synthetic jobs with
real browser episodes (the rest of the matrix).
"""

from __future__ import annotations

import asyncio
import time

from workers.contract import (
    EpisodeTimings,
    EvalResult,
    JobResult,
    StepRecord,
    SyntheticEpisodes,
    TaskPayload,
    TestVerdict,
)
from workers.kinds.tasks._contract import EpisodeSpec


async def run_synthetic(spec: EpisodeSpec, task: TaskPayload, behaviour: SyntheticEpisodes) -> JobResult:
    started, clock = time.time(), time.perf_counter()
    if behaviour.duration_s:
        await asyncio.sleep(behaviour.duration_s)
    fails = task.task_id in behaviour.fail_tasks
    tests = [TestVerdict(name="runs", passed=True), TestVerdict(name="behaves", passed=not fails)]
    passed = sum(t.passed for t in tests)
    evaluation = EvalResult(success=not fails, passed=passed, total=len(tests), psr=passed / len(tests), tests=tests)
    elapsed = time.perf_counter() - clock
    return JobResult(
        job_id=spec.job_id,
        attempt=spec.attempt,
        outcome="failed" if fails else "passed",
        stop_reason="done",
        evaluation=evaluation,
        steps=[StepRecord(index=0, action="done", ok=True, latency_s=elapsed)],
        timings=EpisodeTimings(agent_s=elapsed, total_s=elapsed),
        started_at=started,
        finished_at=time.time(),
    )
