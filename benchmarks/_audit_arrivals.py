"""When each attempt's result reached the driver: the audit benchmarks' measure of a job's time after its verdict."""

from __future__ import annotations

import time
from collections.abc import Iterator
from contextlib import contextmanager

from scratchworld_dist._run import AttemptRecorder
from scratchworld_dist.sweep import JobSpec
from workers.contract import JobResult


@contextmanager
def arrivals() -> Iterator[dict[tuple[str, int], float]]:
    """When each attempt's result reached the driver (its recorder), by (job id, attempt)."""
    seen: dict[tuple[str, int], float] = {}
    record = AttemptRecorder.__call__

    def timed(self: AttemptRecorder, job: JobSpec, result: JobResult) -> None:
        seen[(job.job_id, result.attempt)] = time.time()
        record(self, job, result)

    AttemptRecorder.__call__ = timed  # type: ignore[method-assign]
    try:
        yield seen
    finally:
        AttemptRecorder.__call__ = record  # type: ignore[method-assign]
