"""Workers of one node start their jobs together: none gets a job while another of its node still opens
its editors, and one that Ray cannot place holds them back for a bounded time only (a real local Ray, one
node; synthetic workers whose openings take set times)."""

from __future__ import annotations

import threading
import time

import pytest
import ray

from scratchworld_dist.scheduling import LostNode, Scheduler, SchedulerStats, WorkerPool
from scratchworld_dist.scheduling._scheduler import UNPLACED_HOLD_S
from scratchworld_dist.sweep import JobSpec, worker_job
from tests.scratchworld_dist.scheduling.test_admission import jobs, read_task_payload
from workers.contract import JobResult, SyntheticEpisodes
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint

pytestmark = pytest.mark.ray

SLOW_WARM_S = 3.0


class OpeningAtStart:
    """Hears each job as it is sent, and notes how many workers were still opening their editors then."""

    def __init__(self) -> None:
        self.stats: SchedulerStats | None = None
        self.counts: list[int] = []
        self.times: list[float] = []

    def started(self, job: JobSpec, attempt: int, worker: int) -> None:
        assert self.stats is not None
        self.counts.append(self.stats.warming)
        self.times.append(time.monotonic())

    def finished(self, job: JobSpec, result: JobResult, *, retried: bool) -> None:
        pass

    def node_lost(self, node: LostNode) -> None:
        pass


@pytest.mark.parametrize("warm_s", [[0.0, SLOW_WARM_S], [SLOW_WARM_S, 0.0]], ids=["second-slower", "first-slower"])
def test_no_worker_starts_a_job_while_another_of_its_node_opens_its_editors(
    shared_ray: int, warm_s: list[float]
) -> None:
    planned = jobs(None, harness=kind_fingerprint(harness_fingerprint(), "tasks").digest)  # what workers check
    pool = WorkerPool(2, 1, SyntheticEpisodes(duration_s=0.1, warm_s=warm_s))
    payloads = {job.task_id: ray.put(read_task_payload(job)) for job in planned}
    finished: list[JobResult] = []
    heard = OpeningAtStart()
    timeout_s = 120.0
    scheduler = Scheduler(
        pool, payloads, timeout_s=timeout_s, retries=0, on_result=lambda _, r: finished.append(r), sends=worker_job,
        watcher=heard, unplaced_hold_s=timeout_s,
    )  # fmt: skip
    # The hold is the timeout: a worker whose process is slow to start on a busy machine (the hold counts from the
    # call that asked it to open) must not pass for one Ray cannot place (the next test covers that case).
    heard.stats = scheduler.stats
    warming_seen: list[int] = []
    driver = threading.Thread(target=scheduler.run, args=([(job, 1) for job in planned],))
    try:
        driver.start()
        deadline = time.monotonic() + 300  # a hang detector: Ray starts the workers slowly on a loaded machine
        while driver.is_alive():
            assert time.monotonic() < deadline, scheduler.stats
            warming_seen.append(scheduler.stats.warming)
            driver.join(timeout=0.05)
    finally:
        pool.close()
    assert 1 in warming_seen  # the slower worker was seen opening alone, the other one waiting
    assert heard.counts and heard.counts == [0] * len(heard.counts)
    assert sorted(r.job_id for r in finished) == sorted(job.job_id for job in planned)
    assert all(r.outcome == "passed" for r in finished)


def test_a_worker_ray_cannot_place_holds_the_others_back_for_the_unplaced_hold_only(shared_ray: int) -> None:
    """A pool sized for one browser slot more than the Ray offers leaves its last worker pending for good. It
    may yet land on the others' node, so they wait for it, but only for ``unplaced_hold_s``: not for the
    episode timeout, which would stall every run whose cluster is short of a slot."""
    hold_s, timeout_s = 12.0, 240.0  # the hold outlasts Ray starting the placed workers on an idle machine
    assert hold_s < UNPLACED_HOLD_S  # the default is the production value; a run this long would not prove more
    planned = jobs(None, harness=kind_fingerprint(harness_fingerprint(), "tasks").digest)
    pool = WorkerPool(shared_ray + 1, 1, SyntheticEpisodes(duration_s=0.1))
    payloads = {job.task_id: ray.put(read_task_payload(job)) for job in planned}
    finished: list[JobResult] = []
    heard = OpeningAtStart()
    scheduler = Scheduler(
        pool, payloads, timeout_s=timeout_s, retries=0, on_result=lambda _, r: finished.append(r),
        sends=worker_job, watcher=heard, unplaced_hold_s=hold_s,
    )  # fmt: skip
    heard.stats = scheduler.stats
    driver = threading.Thread(target=scheduler.run, args=([(job, 1) for job in planned],))
    began = time.monotonic()
    try:
        driver.start()
        driver.join(timeout=timeout_s / 2)  # a hang detector, well inside the timeout it must not wait for
        assert not driver.is_alive(), scheduler.stats
    finally:
        pool.close()
    assert sorted(r.job_id for r in finished) == sorted(job.job_id for job in planned)
    assert all(r.outcome == "passed" for r in finished)
    assert heard.times[0] - began >= hold_s  # the pending worker was waited for while it might still land here
