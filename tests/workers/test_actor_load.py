"""A worker's load: the browsers' memory is read at most every ``USAGE_MAX_AGE_S`` (reading every process's PSS
costs tens of milliseconds, after every job), the node's available memory every time (admission decides on it)."""

from __future__ import annotations

import time

from workers.actor import JobWorker
from workers.actor._job_worker import USAGE_MAX_AGE_S


async def test_the_browsers_memory_is_read_again_only_once_it_is_old() -> None:
    worker = JobWorker(0)
    first = await worker.load()
    assert worker._usage is not None
    read_at, usage = worker._usage
    again = await worker.load()
    assert worker._usage == (read_at, usage) and again.browser_pss_bytes == first.browser_pss_bytes
    worker._usage = (time.monotonic() - USAGE_MAX_AGE_S, usage)  # as if read that long ago
    await worker.load()
    assert worker._usage[0] > read_at
