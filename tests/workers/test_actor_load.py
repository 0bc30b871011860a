"""A worker's load: the browsers' memory is read at most every ``USAGE_MAX_AGE_S`` (reading every process's PSS
walks their page tables: a tenth of a second and more), with the editors counted at that moment, so that memory
per editor is one moment's; the node's available memory every time (admission decides on it)."""

from __future__ import annotations

import time

from workers.actor import JobWorker
from workers.actor._job_worker import USAGE_MAX_AGE_S


async def test_the_browsers_memory_is_read_again_only_once_it_is_old() -> None:
    worker = JobWorker(0)
    first = await worker.load()
    assert worker._usage is not None
    read_at, usage, editors = worker._usage
    assert first.editors == editors == 0  # no browser yet
    again = await worker.load()
    assert worker._usage == (read_at, usage, editors) and again.browser_pss_bytes == first.browser_pss_bytes
    worker._usage = (time.monotonic(), usage, 5)  # as if just read with 5 editors
    assert (await worker.load()).editors == 5  # the editors of the reading reported, not a later count
    worker._usage = (time.monotonic() - USAGE_MAX_AGE_S, usage, 5)  # as if read that long ago
    assert (await worker.load()).editors == 0  # read again: the editors held now
    assert worker._usage[0] > read_at
