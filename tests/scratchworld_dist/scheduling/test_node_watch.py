"""A node that leaves the cluster mid-run is named, and the job it held is decided on another node.

Two Ray nodes of this machine (``ray.cluster_utils.Cluster``, on 127.0.0.1), a worker on each; the
second node is removed (its raylet and workers killed) while its worker holds a job. Without root this
is the partition test's counterpart (``test_hosts_share_nothing.py`` takes a real link down).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from typing import Any

import pytest
import ray
from ray.cluster_utils import Cluster

from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.scheduling import LostNode, Scheduler, WorkerPool
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import JobSpec, worker_job
from tests.conftest import REPO
from workers.contract import AgentRef, EpisodeClock, JobResult, SyntheticEpisodes
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint

pytestmark = [pytest.mark.ray, pytest.mark.slow]

LOOPBACK = "127.0.0.1"
HEALTH_CHECKS = {"health_check_period_ms": 500, "health_check_timeout_ms": 500, "health_check_failure_threshold": 4}
"""The head declares a silent node dead within seconds."""


@pytest.fixture
def two_nodes() -> Iterator[tuple[Cluster, Any]]:
    cluster = Cluster(
        initialize_head=True,
        head_node_args={
            "num_cpus": 1, "resources": {"browser": 1}, "include_dashboard": False, "_system_config": HEALTH_CHECKS,
        },
    )  # fmt: skip
    try:
        leaving = cluster.add_node(num_cpus=1, resources={"browser": 1}, node_ip_address=LOOPBACK)
        cluster.wait_for_nodes()
        ray.init(address=cluster.address, log_to_driver=False, configure_logging=False)
        yield cluster, leaving
    finally:
        ray.shutdown()
        cluster.shutdown()


def planned_jobs() -> tuple[list[JobSpec], dict[str, Any]]:
    """Four jobs of our suite, and their tasks' payloads."""
    contents = [read_task(task) for task in load_suite(REPO / "tasks").tasks[:4]]
    matrix = EpisodeMatrix(
        models=[None],
        modes=["composite"],
        agent=AgentRef(name="oracle"),
        tasks=contents,
        seeds=[0],
        max_steps=5,
        harness=kind_fingerprint(harness_fingerprint(), "tasks").digest,
        episode_clock=EpisodeClock(mode="virtual"),
    )
    return list(plan_jobs(matrix)), {content.task.id: content.payload for content in contents}


class Watcher:
    """Hears the scheduler: the attempts sent, their results, the nodes lost."""

    def __init__(self) -> None:
        self.sent: list[tuple[str, int, int]] = []
        self.results: list[JobResult] = []
        self.lost: list[LostNode] = []

    def started(self, job: JobSpec, attempt: int, worker: int) -> None:
        self.sent.append((job.job_id, attempt, worker))

    def finished(self, job: JobSpec, result: JobResult, *, retried: bool) -> None:
        self.results.append(result)

    def node_lost(self, node: LostNode) -> None:
        self.lost.append(node)


@pytest.mark.timeout(600)
def test_a_node_that_leaves_is_named_and_its_job_decided_elsewhere(two_nodes: tuple[Cluster, Any]) -> None:
    cluster, leaving = two_nodes
    jobs, tasks = planned_jobs()
    pool = WorkerPool(2, 1, SyntheticEpisodes(duration_s=3))
    nodes = [info.node_id for info in ray.get([handle.info.remote() for handle in pool.handles], timeout=120)]
    assert sorted(nodes) == sorted({leaving.node_id, cluster.head_node.node_id})  # a worker on each node
    doomed = nodes.index(leaving.node_id)
    payloads = {task_id: ray.put(payload) for task_id, payload in tasks.items()}
    heard = Watcher()
    scheduler = Scheduler(
        pool, payloads, timeout_s=120, retries=1, on_result=lambda *_: None, sends=worker_job, watcher=heard
    )
    driver = threading.Thread(target=scheduler.run, args=([(job, 1) for job in jobs],))
    try:
        driver.start()
        deadline = time.monotonic() + 300  # a hang detector: Ray starts workers slowly on a loaded machine
        while not any(worker == doomed for _, _, worker in heard.sent):
            assert time.monotonic() < deadline and driver.is_alive(), heard.sent
            time.sleep(0.05)
        cluster.remove_node(leaving, allow_graceful=False)
        driver.join(timeout=300)
        assert not driver.is_alive()
    finally:
        pool.close()

    (lost,) = heard.lost
    address = LOOPBACK  # both nodes listen on loopback only
    assert (lost.node_id, lost.address, lost.workers) == (leaving.node_id, address, (doomed,))
    assert lost.reason and lost.name.endswith(f"({address}, node {leaving.node_id[:8]})")
    assert scheduler.stats.nodes_lost == 1
    verdicts = [result for result in heard.results if result.outcome != "error"]
    assert sorted(result.job_id for result in verdicts) == sorted(job.job_id for job in jobs)  # each once
    errors = [result for result in heard.results if result.outcome == "error"]
    assert [result.error_class for result in errors] == ["worker_died"]
    (again,) = [result for result in verdicts if result.job_id == errors[0].job_id]
    assert again.attempt == 2 and again.worker is not None and again.worker.node_id == cluster.head_node.node_id
