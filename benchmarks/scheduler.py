"""Prints the sweep engine's own costs, with synthetic (browserless) episodes.

    .venv/bin/python benchmarks/scheduler.py [--jobs 2000] [--max-nodes 4] [--slots 2] [--duration 0.5]

1. Planning: time to plan a 100k-job matrix and to find the decided jobs of a 100k-row run.
2. Driver overhead per job: zero-length episodes through the real pipeline (Ray actors, driver
   loop, journal commits, compaction); the driver's CPU time per job and wall time per job.
3. Scaling: simulated nodes (``ray.cluster_utils.Cluster``, each with ``--slots`` browser slots)
   running fixed-length episodes, 1..N nodes; throughput per node against one node.

All nodes share this machine's cores, so the scaling figure measures the scheduler (sleeping
episodes), not CPU-bound editors.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER", "0")

import ray
from ray.cluster_utils import Cluster

from scratchworld_dist._run import AttemptRecorder
from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.results import RunStore, record_of
from scratchworld_dist.scheduling import Scheduler, WorkerPool, ray_runtime
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import JobSpec, worker_job
from workers.contract import JobResult, ModelSpec, SyntheticEpisodes

REPO = Path(__file__).resolve().parents[1]
CONTENTS = [read_task(task) for task in load_suite(REPO / "tasks").tasks]


def jobs(count: int) -> list[JobSpec]:
    seeds = list(range(-(-count // len(CONTENTS))))
    return list(
        plan_jobs(
            EpisodeMatrix(models=[None], modes=["composite"], agent="oracle", tasks=CONTENTS, seeds=seeds, max_steps=5)
        )
    )[:count]


def planning() -> None:
    models: list[ModelSpec | None] = [ModelSpec(name=f"m{i}", model=f"openai/m{i}") for i in range(4)]
    started = time.perf_counter()
    planned = list(
        plan_jobs(
            EpisodeMatrix(
                models=models,
                modes=["composite", "primitive"],
                agent="llm",
                tasks=CONTENTS,
                seeds=list(range(1042)),
                max_steps=50,
            )
        )
    )
    plan_s = time.perf_counter() - started
    with tempfile.TemporaryDirectory() as tmp:
        store = RunStore(Path(tmp))
        store.open_for_writing()
        now = time.time()
        for job in planned:
            result = JobResult(
                job_id=job.job_id, attempt=1, outcome="passed", stop_reason="done", started_at=now, finished_at=now
            )
            store.commit(record_of(job, result, run_name="b", suite_hash="s", artifact_dir=None))
        store.close()
        started = time.perf_counter()
        decided = RunStore(Path(tmp)).attempts()
        lookup_s = time.perf_counter() - started
        todo = [job for job in planned if not decided.get(job.job_id, (0, False))[1]]
    print(
        f"planning: {len(planned)} jobs planned in {plan_s:.2f} s; decided jobs of a {len(decided)}-row run "
        f"found in {lookup_s:.2f} s ({len(todo)} left)"
    )


def run_jobs(job_list: list[JobSpec], slots: int, duration: float) -> tuple[float, float]:
    """(wall seconds, driver CPU seconds) to run the jobs; Ray must already be initialised."""
    with tempfile.TemporaryDirectory() as tmp:
        store = RunStore(Path(tmp))
        store.open_for_writing()
        pool = WorkerPool(slots, 1, SyntheticEpisodes(duration_s=duration))
        ray.get([handle.info.remote() for handle in pool.handles])  # actors up before the clock starts
        payloads = {c.task.id: ray.put(c.payload) for c in CONTENTS}
        scheduler = Scheduler(
            pool,
            payloads,
            timeout_s=600,
            retries=0,
            on_result=AttemptRecorder(store, "bench", "s", "h"),
            sends=worker_job,
        )
        wall, cpu = time.perf_counter(), time.process_time()
        scheduler.run((job, 1) for job in job_list)
        store.close()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        assert scheduler.stats.outcomes["passed"] == len(job_list)
        pool.close()
    return wall, cpu


def overhead(count: int, slots: int) -> None:
    with ray_runtime(None, slots) as available:
        wall, cpu = run_jobs(jobs(count), available, 0.0)
    print(
        f"driver overhead: {count} zero-length jobs on {available} workers: driver CPU {cpu / count * 1000:.2f} "
        f"ms/job, wall {wall / count * 1000:.2f} ms/job ({count / wall:.0f} jobs/s)"
    )


def scaling(max_nodes: int, slots: int, duration: float, per_slot: int) -> None:
    base: float | None = None
    for nodes in range(1, max_nodes + 1):
        cluster = Cluster(
            initialize_head=True,
            head_node_args={"num_cpus": 1, "resources": {"browser": slots}, "include_dashboard": False},
        )
        try:
            for _ in range(nodes - 1):
                cluster.add_node(num_cpus=1, resources={"browser": slots})
            cluster.wait_for_nodes()
            ray.init(address=cluster.address, log_to_driver=False)
            count = nodes * slots * per_slot
            wall, cpu = run_jobs(jobs(count), nodes * slots, duration)
            throughput = count / wall
            base = base or throughput
            ideal = nodes * slots / duration
            print(
                f"scaling: {nodes} node(s) x {slots} slot(s): {count} jobs of {duration:g} s in {wall:.2f} s = "
                f"{throughput:.2f} jobs/s ({throughput / ideal:.0%} of ideal; {throughput / (base * nodes):.0%} "
                f"of linear from 1 node); driver CPU {cpu / count * 1000:.2f} ms/job"
            )
        finally:
            ray.shutdown()
            cluster.shutdown()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=2000, help="zero-length jobs for the overhead figure")
    parser.add_argument("--max-nodes", type=int, default=4)
    parser.add_argument("--slots", type=int, default=2, help="browser slots per simulated node")
    parser.add_argument("--duration", type=float, default=0.5, help="seconds per episode when scaling")
    parser.add_argument("--per-slot", type=int, default=20, help="jobs per slot when scaling")
    args = parser.parse_args()
    planning()
    overhead(args.jobs, args.slots)
    scaling(args.max_nodes, args.slots, args.duration, args.per_slot)


if __name__ == "__main__":
    main()
