"""``run_regrade``: a source run's stored projects evaluated again, over Ray like any sweep, into a new run.

The sweep's machinery does the work: the same worker pool (recycled evaluation editors), the same
scheduler (timeouts, retries, dead workers), the same journaled store; resuming skips decided jobs.
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import ray
from pydantic import BaseModel
from rich.console import Console

from scratchworld_dist._console import make_console
from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.tasks.regrade._manifest import regrade_manifest
from scratchworld_dist.kinds.tasks.regrade._plan import RegradeJob, RegradePlan, plan_regrade
from scratchworld_dist.kinds.tasks.regrade._record import RegradeRecorder
from scratchworld_dist.kinds.tasks.regrade._source import read_source
from scratchworld_dist.kinds.tasks.report import VerdictChange, verdict_changes
from scratchworld_dist.results import RunManifest, RunStore, Session, now, write_manifest
from scratchworld_dist.scheduling import (
    Scheduler,
    WorkerPool,
    agreed_harness,
    inspect_nodes,
    live_progress,
    pages_per_worker,
    ray_runtime,
)
from workers.contract import MIB, EvaluationClock, EvaluationPage, EvaluationProfile, EvaluationRender, NodeReport
from workers.kinds import kind_fingerprint
from workers.node import describe_node, harness_fingerprint


class RegradeSummary(BaseModel):
    """What one ``run_regrade`` call did, and how the regrade's verdicts stand against the source's."""

    run_dir: Path
    planned: int
    already_decided: int
    sent: int
    outcomes: dict[str, int]
    retried: int
    unchanged: int
    changed: list[VerdictChange]
    without_project: list[str]
    """Source jobs that stored no project, as ``task seed mode``: not regraded."""

    elapsed_s: float
    """Wall time of this call's regrades, Ray's and the workers' start included (0 when none was sent)."""


class _RayTarget(BaseModel):
    """Where regrades run: a cluster's address, or a private Ray with ``local_slots`` browser slots."""

    address: str | None
    local_slots: int | None
    connect_timeout_s: float


def run_regrade(
    source_dir: Path,
    out: Path,
    *,
    suite: Path | None = None,
    profile: EvaluationProfile | None = None,
    clock: EvaluationClock | None = None,
    render: EvaluationRender | None = None,
    page: EvaluationPage | None = None,
    address: str | None = None,
    connect_timeout_s: float = 30.0,
    force: bool = False,
    console: Console | None = None,
) -> RegradeSummary:
    """Regrade ``source_dir`` into ``out``, or resume that regrade; on a cluster, its nodes are checked first.

    ``address``: the cluster to join; default ``RAY_ADDRESS``, as for a sweep, else a private local Ray."""
    console = console or make_console(stderr=True)
    address = address or os.environ.get("RAY_ADDRESS") or None
    if out.resolve() == source_dir.resolve():
        raise RunDirError(f"{out}: --out is the source run itself; a regrade writes a new run directory")
    source = read_source(source_dir)
    if address is None:  # a private local Ray: this machine is the only node
        local = describe_node()
        plan = plan_regrade(source, kind_fingerprint(local.harness, "tasks"), suite, profile, clock, render, page)
        return _run_plan(plan, out, [local], None, connect_timeout_s, force, console)
    with ray_runtime(address, None, connect_timeout_s):
        nodes = inspect_nodes()
        harness = kind_fingerprint(agreed_harness(nodes, harness_fingerprint()), "tasks")  # regrades: tasks
        plan = plan_regrade(source, harness, suite, profile, clock, render, page)
        return _run_plan(plan, out, nodes, address, connect_timeout_s, force, console)


def _run_plan(
    plan: RegradePlan,
    out: Path,
    nodes: list[NodeReport],
    address: str | None,
    connect_timeout_s: float,
    force: bool,
    console: Console,
) -> RegradeSummary:
    manifest = regrade_manifest(plan, out, force)
    store = RunStore(out)
    store.open_for_writing()
    try:
        todo = store.undecided(plan.jobs)
        local_slots = None
        if address is None:
            local_slots = plan.limits.browser_slots or os.cpu_count() or 1  # no model to wait on: one per core
            nodes = [nodes[0].model_copy(update={"browser_slots": local_slots})]
        session = Session.begin(len(todo), [node.summary() for node in nodes])
        manifest.sessions.append(session)
        write_manifest(out, manifest)
        console.print(
            f"regrade of {plan.source.path} under {plan.suite.name} "
            f"({plan.profile}, {plan.clock} clock, render {plan.render}, {plan.page} page): "
            f"{len(plan.jobs)} job(s), {len(plan.jobs) - len(todo)} already decided, {len(todo)} to run -> {out}",
            markup=False,
        )
        sent, outcomes, retried = 0, {"passed": 0, "failed": 0, "error": 0}, 0
        started = time.perf_counter()
        if todo:
            target = _RayTarget(address=address, local_slots=local_slots, connect_timeout_s=connect_timeout_s)
            sent, outcomes, retried = _execute(plan, manifest, store, todo, target, console)
        elapsed = time.perf_counter() - started if todo else 0.0
        session.finished_at = now()
        session.submitted = sent
        write_manifest(out, manifest)
    finally:
        store.close()
    planned = {job.job_id for job in plan.jobs}
    rows = [r for r in manifest.current_rows(store.job_rows()) if r.job_id in planned]
    changed, unchanged = verdict_changes([job.source.row for job in plan.jobs], rows)
    return RegradeSummary(
        run_dir=out,
        planned=len(plan.jobs),
        already_decided=len(plan.jobs) - len(todo),
        sent=sent,
        outcomes=outcomes,
        retried=retried,
        unchanged=unchanged,
        changed=changed,
        without_project=[f"{r.task_id} seed {r.seed} {r.mode}" for r in plan.source.without_project],
        elapsed_s=elapsed,
    )


def _execute(
    plan: RegradePlan,
    manifest: RunManifest,
    store: RunStore,
    todo: list[tuple[RegradeJob, int]],
    target: _RayTarget,
    console: Console,
) -> tuple[int, dict[str, int], int]:
    """Run ``todo`` on Ray; returns attempts sent, final outcomes and retries."""
    limits = plan.limits
    needed = {job.task_id for job, _ in todo}
    with ray_runtime(target.address, target.local_slots, target.connect_timeout_s) as slots:
        cores = os.cpu_count() or 1
        if target.local_slots is None:  # a cluster: the cores of all its nodes
            cores = int(ray.cluster_resources().get("CPU", cores))
        at_once = min(len(todo), limits.max_in_flight or len(todo))
        pages = pages_per_worker(limits, slots, cores)
        pool = WorkerPool(slots, pages, None, limits.memory_reserve_mb * MIB, at_once)
        payloads = {c.task.id: ray.put(c.payload) for c in plan.contents if c.task.id in needed}
        record = RegradeRecorder(store, manifest.run_name, manifest.suite, plan.source.steps)
        scheduler = Scheduler(
            pool,
            payloads,
            timeout_s=limits.episode_timeout_s,
            retries=limits.retries,
            on_result=record,
            sends=RegradeJob.worker_job,
            max_in_flight=limits.max_in_flight,
        )
        console.print(pool.describe(slots))
        try:
            with live_progress(scheduler.stats, len(todo), console):
                scheduler.run(todo)
        finally:
            pool.close(keep=scheduler.settled)
    stats = scheduler.stats
    return stats.submitted, stats.outcomes, stats.retried
