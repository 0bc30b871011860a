"""``run_sweep``: from a config to committed results, resuming whatever the run directory holds.

The run directory is the durable record: its manifest says which sweep it holds, its results
say which jobs are decided. Running the same config again skips decided jobs, re-runs the rest
(errors included, with the next attempt number) and never touches committed rows.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

import ray
from ray.exceptions import RayError
from rich.console import Console

from scratchworld_dist._console import make_console
from scratchworld_dist._errors import ConfigError, RunDirError
from scratchworld_dist._run_events import SweepWatcher
from scratchworld_dist._run_spans import JobSpans
from scratchworld_dist._run_start import sized_pool, start_beside_preflight, warm_needs
from scratchworld_dist._run_summary import RunSummary
from scratchworld_dist._sweep_manifest import checked_manifest
from scratchworld_dist.kinds import job_kind
from scratchworld_dist.memory import JobItems, StoreInfo, start_memory_service
from scratchworld_dist.results import (
    MANIFEST_NAME,
    VIDEO_FILE,
    VIDEO_INFO_FILE,
    EventLog,
    KindRows,
    RunManifest,
    RunStore,
    Session,
    SweepStart,
    now,
    record_of,
    write_manifest,
)
from scratchworld_dist.results.remote._sync import RemoteRun, open_remote
from scratchworld_dist.scheduling import (
    ProgressOptions,
    Scheduler,
    WorkerPool,
    admitted_slots,
    agreed_harness,
    inspect_nodes,
    live_progress,
    ray_runtime,
    refuse_broken,
    settle,
    shown_mode,
    worker_logs_dir,
)
from scratchworld_dist.sweep import JobSpec, RunPlan, SuiteInfo, SweepConfig, plan_run, worker_job
from scratchworld_dist.trackers import TrackerFeed, configured_trackers, run_files, start_trackers
from workers.contract import (
    JobResult,
    ModelSpec,
    NodeReport,
    WorkerJob,
)
from workers.llm import RayLimiterHandle, get_or_create_limiter, model_key
from workers.node import describe_node, harness_fingerprint
from workers.tracing import TracingConfigError, tracing_active


class AttemptRecorder:
    """Commits every finished attempt: artifacts first, then its rows (the commit point)."""

    def __init__(self, store: RunStore, run_name: str, suite: SuiteInfo, memory: Any = None) -> None:
        """``memory``: the memory service, handed each job's proposals before its rows are committed."""
        self.store = store
        self.run_name = run_name
        self.suite = suite
        self.memory = memory

    def __call__(self, job: JobSpec, result: JobResult) -> None:
        if self.memory is not None and job.memory is not None:
            info = StoreInfo(model=job.model_name, mode=job.mode, seed=job.seed)
            entry = JobItems(job_id=job.job_id, wave=job.memory.wave, outcome=result.outcome, items=result.memory_items)
            ray.get(self.memory.record.remote(job.memory.store, info, entry))
        artifact_dir = None
        if result.final_project is not None:
            artifact_dir = self.store.write_artifact(job.job_id, result.attempt, "final.sb3", result.final_project)
        for digest, image in result.images.items():  # referenced from the prompts in trajectory.jsonl
            self.store.write_artifact(job.job_id, result.attempt, f"images/{digest}.png", image)
        if result.steps:
            lines = "".join(step.model_dump_json() + "\n" for step in result.steps)
            artifact_dir = self.store.write_artifact(job.job_id, result.attempt, "trajectory.jsonl", lines.encode())
        if result.video is not None:  # an artifact only: the viewer plays it beside the steps
            self.store.write_artifact(job.job_id, result.attempt, VIDEO_FILE, result.video.mp4)
            info = result.video.info.model_dump_json(indent=1).encode()
            artifact_dir = self.store.write_artifact(job.job_id, result.attempt, VIDEO_INFO_FILE, info)
        record = record_of(
            job,
            result,
            run_name=self.run_name,
            suite_hash=self.suite.hash,
            artifact_dir=artifact_dir,
            stability=self.suite.stability,
        )
        self.store.commit(record)


def run_sweep(
    config: SweepConfig,
    *,
    force: bool = False,
    console: Console | None = None,
    skip_broken_models: bool = False,
    progress: ProgressOptions | None = None,
) -> RunSummary:
    """Run or resume the sweep. On a cluster, its nodes are checked first (the driver's code, one editor
    and one browser among them) and the jobs are planned under their environment. Before any job
    starts, the models the jobs to run call are checked (``PreflightError`` names the broken ones, unless
    ``skip_broken_models`` leaves their jobs out). ``progress``: how progress is shown (default: live on a
    terminal, plain lines elsewhere); every attempt is also an event in the run directory's ``events.jsonl``."""
    console = console or make_console(stderr=True)
    shown = progress or ProgressOptions()
    try:
        tracing_active()  # an exporter OTEL_TRACES_EXPORTER names but no package provides: said before any job
    except TracingConfigError as exc:
        raise ConfigError(str(exc)) from None
    if config.ray.address is None:  # a private local Ray: this machine is the only node
        local = describe_node()
        return _run_plan(plan_run(config, local.harness), [local], force, console, skip_broken_models, shown)
    with ray_runtime(config.ray.address, config.limits.browser_slots, config.ray.connect_timeout_s):
        nodes = inspect_nodes()
        harness = agreed_harness(nodes, harness_fingerprint())
        slots = sum(node.browser_slots for node in nodes)
        console.print(f"{len(nodes)} node(s) with {slots} browser slot(s) run harness {harness.digest}")
        return _run_plan(plan_run(config, harness), nodes, force, console, skip_broken_models, shown)


def _run_plan(
    plan: RunPlan,
    nodes: list[NodeReport],
    force: bool,
    console: Console,
    skip_broken_models: bool,
    progress: ProgressOptions,
) -> RunSummary:
    config = plan.config
    remote = open_remote(config, console)  # before anything else: a bucket that cannot take the run stops it here
    try:
        with contextlib.ExitStack() as ray_scope:
            return _run_in(plan, nodes, force, console, skip_broken_models, progress, remote, ray_scope)
    finally:
        if remote is not None:
            note = remote.close(config.storage.drain_timeout_s)
            console.print(note or f"all results are in {remote.location.url}", markup=False)


def _run_in(
    plan: RunPlan,
    nodes: list[NodeReport],
    force: bool,
    console: Console,
    skip_broken_models: bool,
    progress: ProgressOptions,
    remote: RemoteRun | None,
    ray_scope: contextlib.ExitStack,
) -> RunSummary:
    """The run itself; a private Ray started beside the preflight lives in ``ray_scope`` (until the run ends)."""
    config = plan.config
    run_dir = config.run_dir()
    store = RunStore(run_dir)
    store.listener = remote
    manifest = checked_manifest(plan, run_dir, force)
    configured_trackers(config.loggers)  # a tracker whose package is missing: refused before a model is called
    if config.model_cache is not None:
        _open_model_cache(config.model_cache.dir)
    # Before the run directory is touched: a broken model stops the run leaving nothing behind.
    undecided_jobs = [job for job, _ in store.undecided(plan.jobs)]
    start = start_beside_preflight(plan, undecided_jobs, nodes, ray_scope)
    preflight, early = start.preflight, start.workers
    refuse_broken(preflight, skip_broken_models)
    store.open_for_writing()
    feed: TrackerFeed | None = None
    events: EventLog | None = None
    watcher: SweepWatcher | None = None
    spans: JobSpans | None = None
    status = "failed"
    try:
        events = EventLog(run_dir)
        feed = start_trackers(plan, manifest, run_dir, partial(console.print, markup=False, highlight=False))
        undecided = store.undecided(plan.jobs)
        todo = settle(preflight, plan, undecided, console)
        if early is not None and not early.serve([job for job, _ in todo]):
            early.pool.close()  # sized for jobs the preflight left out
            early = None
        local_slots = None
        if config.ray.address is None:  # admission on this machine, measured only when there is work
            if early is not None:
                local_slots = early.slots
                for line in early.admission:
                    console.print(line)
            else:
                todo_jobs = [job for job, _ in todo]
                local_slots = admitted_slots(config.limits, todo_jobs, nodes[0].harness.digest, console.print)
            nodes = [nodes[0].model_copy(update={"browser_slots": local_slots})]
        session = Session.begin(len(todo), [node.summary() for node in nodes])
        session.preflight = preflight
        manifest.sessions.append(session)
        _save_manifest(run_dir, manifest, remote)
        console.print(
            f"{config.name}: {len(plan.jobs)} job(s) planned over {plan.suite.tasks} task(s) of {plan.suite.name}; "
            f"{len(plan.jobs) - len(undecided)} already decided, {len(todo)} to run"
            + (f" ({len(undecided) - len(todo)} left out)" if len(todo) < len(undecided) else "")
            + f" -> {run_dir}",
            markup=False,  # the suite's name and the path are the user's text
        )
        decided = len(plan.jobs) - len(undecided)
        events.write(
            SweepStart(
                session=len(manifest.sessions), run_name=config.name, planned=len(plan.jobs), already_decided=decided,
                to_run=len(todo), host=session.host, pid=session.pid, tags=manifest.tags,
            )
        )  # fmt: skip
        say_errors = shown_mode(progress.mode, console) != "none"
        followers = [feed.hear] if feed is not None else []
        if tracing_active():
            spans = JobSpans(worker_job, config.name, len(manifest.sessions))
            followers.append(spans.hear)
        watcher = SweepWatcher(events, len(manifest.sessions), console, say_errors, followers)
        summary = RunSummary(
            run_dir=run_dir,
            planned=len(plan.jobs),
            already_decided=decided,
            left_out=len(undecided) - len(todo),
            sent=0,
            outcomes={"passed": 0, "failed": 0, "error": 0},
            attempts=0,
            retried=0,
        )
        if todo:
            sends = spans.sends if spans is not None else worker_job
            runtime = (
                contextlib.nullcontext(local_slots)
                if start.ray_started and local_slots is not None
                else ray_runtime(config.ray.address, local_slots, config.ray.connect_timeout_s)
            )
            pool = early.pool if early is not None else None
            summary = _execute(plan, manifest, store, todo, runtime, console, summary, watcher, progress, sends, pool)
        session.finished_at = now()
        session.submitted = summary.sent
        session.budget_stop = summary.budget_stop
        _save_manifest(run_dir, manifest, remote)
        watcher.end("finished", budget_stop=summary.budget_stop)
        status = "finished"
    except KeyboardInterrupt:
        status = "interrupted"
        if watcher is not None:
            watcher.end("interrupted")
        raise
    except Exception as exc:
        if watcher is not None:
            watcher.end("failed", reason=(str(exc).strip().splitlines() or [type(exc).__name__])[0][:300])
        raise
    finally:
        if spans is not None:
            spans.end(status)
        if events is not None:
            events.close()
        store.close()
        if feed is not None:  # after the store's last commit: the report it is handed is the run's
            _finish_trackers(feed, status, run_dir, manifest, config.benchmark, remote)
        if remote is not None:
            remote.push_rest()
    return summary


def _save_manifest(run_dir: Path, manifest: RunManifest, remote: RemoteRun | None) -> None:
    """Write the run's manifest, and put it in the bucket when the run directory is remote."""
    write_manifest(run_dir, manifest)
    if remote is not None:
        remote.stored(MANIFEST_NAME)


def _finish_trackers(
    feed: TrackerFeed, status: str, run_dir: Path, manifest: RunManifest, benchmark: str, remote: RemoteRun | None
) -> None:
    """Hand the trackers the run's end and its report; record their run ids so that a resumed run continues them."""
    runs = feed.finish(status, partial(run_files, run_dir, benchmark))
    if manifest.trackers is not None and runs != manifest.trackers.runs and (run_dir / MANIFEST_NAME).exists():
        manifest.trackers.runs.update(runs)
        with contextlib.suppress(RunDirError):  # the key is recorded already: a resume finds the runs by it
            _save_manifest(run_dir, manifest, remote)


def _execute(
    plan: RunPlan,
    manifest: RunManifest,
    store: RunStore,
    todo: list[tuple[JobSpec, int]],
    runtime: contextlib.AbstractContextManager[int],
    console: Console,
    summary: RunSummary,
    watcher: SweepWatcher,
    progress: ProgressOptions,
    sends: Callable[[JobSpec, int, float], WorkerJob],
    pool: WorkerPool | None = None,
) -> RunSummary:
    """Run ``todo`` on Ray, within ``runtime`` (which yields the browser slots: a private Ray's admitted ones, or
    the configured cluster's); ``sends`` makes each attempt's worker job (``worker_job``, with its span's
    ``traceparent`` while tracing); ``pool``: workers started for ``todo`` already (beside the preflight)."""
    config = plan.config
    needed = {job.task_id for job, _ in todo}
    local = config.ray.address is None
    with runtime as slots:
        limiters = _rate_limiters([model for job, _ in todo for model in (job.model, *job.extra_models)])
        memory = None
        if plan.memory is not None:
            memory = start_memory_service(
                store.run_dir, config.agent, plan.memory, config.llm.retry, plan.memory_sources
            )
        commit = AttemptRecorder(store, config.name, manifest.suite, memory)
        cores = os.cpu_count() or 1
        if not local:  # a cluster: the cores of all its nodes
            cores = int(ray.cluster_resources().get("CPU", cores))
        jobs = [job for job, _ in todo]
        needs = warm_needs(jobs)
        if pool is None:
            pool = sized_pool(plan, jobs, slots, cores, local=local)
        payloads = {c.task.id: ray.put(c.payload) for c in plan.contents if c.task.id in needed}
        job_kind(config.benchmark, KindRows).store_shared(store, [c for c in plan.contents if c.task.id in needed])
        scheduler = Scheduler(
            pool,
            payloads,
            timeout_s=config.limits.episode_timeout_s,
            retries=config.limits.retries,
            on_result=commit,
            sends=sends,
            max_in_flight=config.limits.max_in_flight,
            budget_usd=config.limits.budget_usd,
            spent_usd=store.cost_usd() if config.limits.budget_usd is not None else 0.0,
            open_editors=needs.open_editors,
            calls_models=needs.calls_models,
            watcher=watcher,
        )
        console.print(pool.describe(slots))
        logs = worker_logs_dir()
        if logs is not None:
            where = "" if config.ray.address is None else " (that folder on each node)"
            console.print(f"worker logs: {logs}{where}", markup=False)
        try:
            with live_progress(scheduler.stats, len(todo), console, progress.mode, progress.interval_s):
                _run_waves(scheduler, todo, memory, console)
        finally:
            pool.close(keep=scheduler.settled)
            del limiters
    stats = scheduler.stats
    budget_stop = None
    if stats.not_started and scheduler.over_budget:
        spent = scheduler.spent_usd + stats.cost_usd
        budget_stop = (
            f"budget of ${config.limits.budget_usd:g} reached (spent ${spent:.4f}); "
            f"{stats.not_started} job(s) not started"
        )
        console.print(budget_stop)
    return summary.model_copy(
        update={
            "sent": stats.submitted,
            "outcomes": stats.outcomes,
            "attempts": stats.attempts,
            "retried": stats.retried,
            "budget_stop": budget_stop,
        }
    )


def _run_waves(scheduler: Scheduler, todo: list[tuple[JobSpec, int]], memory: Any, console: Console) -> None:
    """Run the jobs wave by wave (one wave when the sweep keeps no memory): each wave's jobs are shown
    the snapshot induced from the waves before it. A stream whose induction fails stops there; its
    later jobs stay unstarted (a resume tries again)."""
    waves = sorted({_wave(job) for job, _ in todo})
    broken: set[str] = set()
    for wave in waves:
        batch = _longest_first([(job, attempt) for job, attempt in todo if _wave(job) == wave])
        if memory is not None:
            ready, failed = _with_snapshots(memory, batch, broken)
            for store, reason in failed.items():
                console.print(f"memory {store}: wave {wave} could not be induced ({reason}); a resume tries again")
            broken |= set(failed)
            scheduler.stats.not_started += len(batch) - len(ready)
            batch = ready
        scheduler.run(batch)
        if scheduler.over_budget:
            scheduler.stats.not_started += sum(1 for job, _ in todo if _wave(job) > wave)
            return


def _longest_first(batch: list[tuple[JobSpec, int]]) -> list[tuple[JobSpec, int]]:
    """The jobs by expected length, longest first, in plan order among equals: started last, a long job would
    keep one worker busy while the others stand idle (the demo: primitive episodes after the composite ones
    left one of its two workers idle for the last 7 s)."""
    return sorted(batch, key=lambda item: -item[0].body.expected_length)


def _wave(job: JobSpec) -> int:
    return job.memory.wave if job.memory is not None else 0


def _with_snapshots(
    memory: Any, batch: list[tuple[JobSpec, int]], broken: set[str]
) -> tuple[list[tuple[JobSpec, int]], dict[str, str]]:
    """The wave's jobs, each carrying its stream's snapshot; and the streams whose induction failed."""
    streams = {job.memory.store: job for job, _ in batch if job.memory is not None and job.memory.store not in broken}
    calls = {
        store: memory.snapshot.remote(store, job.memory.wave, job.mode, job.model)  # type: ignore[union-attr]
        for store, job in streams.items()
    }
    snapshots, failed = {}, {}
    for store, call in calls.items():
        try:
            snapshots[store] = ray.get(call)
        except RayError as exc:
            failed[store] = (str(exc).strip().splitlines() or [type(exc).__name__])[-1][:300]
    ready = [
        (job.model_copy(update={"memory_snapshot": snapshots[job.memory.store]}), attempt)
        for job, attempt in batch
        if job.memory is not None and job.memory.store in snapshots
    ]
    return ready, failed


def _open_model_cache(folder: Path) -> None:
    """Create the cache folder here, so a path no one can write is refused before any job runs."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".probe-{os.getpid()}"
        probe.write_bytes(b"")
        probe.unlink()
    except OSError as exc:
        raise ConfigError(f"model_cache.dir: cannot store model replies in {folder}: {exc.strerror or exc}") from None


def _rate_limiters(models: list[ModelSpec | None]) -> list[RayLimiterHandle]:
    """Create each model's cluster-wide limiter here, so it is owned by (and ends with) this driver."""
    limited = {model_key(m): m.rate_limits for m in models if m is not None and m.rate_limits is not None}
    return [get_or_create_limiter(key, limits) for key, limits in limited.items()]
