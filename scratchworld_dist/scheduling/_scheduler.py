"""The driver loop: a bounded number of jobs in flight, results handled as they finish.

Each worker gets at most ``pages`` jobs at a time, so a job's clock starts when it is sent and
a dead worker costs only its own jobs. Failures are classified, never lost:

- a worker that dies (OOM, crash, kill) fails its calls with ``RayActorError``; those attempts
  are recorded as ``worker_died`` and retried, and Ray restarts the worker. Until it answers
  again it gets no job: Ray fails every call sent to a restarting actor, so it would otherwise
  turn the queue into ``worker_died`` errors for as long as its restart takes. A node that leaves
  the cluster (a crash, a partition) takes its workers along: the watcher hears which node it was
  (``NodeWatch``), and its jobs' errors name it;
- a worker that stops answering past a job's timeout plus a grace period is restarted by the
  driver; the overdue job is recorded as ``episode_timeout``, its neighbours are re-sent as the
  same attempt (they did nothing wrong);
- an ``error`` outcome is retried up to ``retries`` times in this run, unless its class is
  permanent (a model that refuses the request will refuse it again);
- once the sweep's model spend reaches its budget, no new attempt is started;
- a worker whose node is short of memory declines a job (``Refusal``): the job goes back to the
  front of the queue as the same attempt, and the worker gets no job until it says memory is back.

Before its first job, each worker opens the editors its share of the jobs will use (``warm``) and
gets no job until they are open: an editor opened while episodes run slows their steps for seconds.
The same holds between the workers of one node, which share its cores: a worker that has opened its
editors gets no job until every other worker of its node has too (or has taken an episode timeout).
"""

from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Generic, Protocol, TypeVar

import ray
from ray.exceptions import GetTimeoutError, RayActorError, RayError

from scratchworld_dist.scheduling._node_watch import LostNode, NodeWatch
from scratchworld_dist.scheduling._pool import WorkerPool
from workers.contract import (
    PERMANENT_ERRORS,
    ErrorClass,
    JobResult,
    Refusal,
    WorkerInfo,
    WorkerJob,
    WorkerLoad,
)

DEADLINE_GRACE_S = 30.0
"""How long past its own timeout a worker may stay silent before the driver restarts it."""

WAIT_SLICE_S = 0.5
"""Longest single ``ray.wait``; bounds how late deadlines are noticed."""

ADMISSION_WAIT_S = 5.0
"""How long a worker that declined a job waits for memory before it answers that it still lacks it."""

UNPLACED_HOLD_S = 60.0
"""How long a worker that has not started yet (Ray has not placed it, or it is still importing) holds back
the workers that have opened their editors: it may be on their node, but it may also wait for a slot for good."""


class Job(Protocol):
    """What the scheduler needs of a job (a sweep's ``JobSpec``, or a regrade's job): its name and its task's
    payload key; what a worker is sent for one of its attempts comes from the scheduler's ``sends``."""

    @property
    def job_id(self) -> str: ...

    @property
    def task_id(self) -> str: ...


J = TypeVar("J", bound=Job)
J_contra = TypeVar("J_contra", bound=Job, contravariant=True)


class SchedulerWatcher(Protocol[J_contra]):
    """Hears each attempt as it is sent and as it ends (the run's events and its log lines)."""

    def started(self, job: J_contra, attempt: int, worker: int) -> None:
        """``attempt`` of ``job`` was sent to ``worker`` (again, when a worker declined it or was restarted)."""

    def finished(self, job: J_contra, result: JobResult, *, retried: bool) -> None:
        """The attempt ended and its result is committed; ``retried``: an error the scheduler sends again."""

    def node_lost(self, node: LostNode) -> None:
        """``node`` left the cluster (Ray declared it dead); its workers take no job until Ray restarts them."""


@dataclass
class _Down:
    """A worker that takes no job yet (it is opening its editors, or it died or was restarted), and the
    call that tells when it answers again."""

    probe: ray.ObjectRef
    since: float
    warming: bool = False
    """It is opening its editors before its first job (not restarting)."""

    warmed: bool = False
    """It has opened them and waits for the other workers of its node to open theirs."""


@dataclass
class _Flight(Generic[J]):
    job: J
    attempt: int
    worker: int
    deadline: float
    sent_at: float
    """Unix time the job was sent: the start of an attempt that never reported back."""

    collateral: bool = False
    """The driver restarted this job's worker because of another job; re-send it unchanged."""


@dataclass
class SchedulerStats:
    """Live counters for the progress display."""

    submitted: int = 0
    in_flight: int = 0
    attempts: int = 0
    retried: int = 0
    """Attempts that ended in error and were sent again."""

    restarts: int = 0
    """Workers the driver restarted because they stopped answering."""

    outcomes: dict[str, int] = field(default_factory=lambda: {"passed": 0, "failed": 0, "error": 0})
    """Final outcomes of jobs finished in this run."""

    cost_usd: float = 0.0
    not_started: int = 0
    """Jobs left unstarted because the budget was reached."""

    nodes_lost: int = 0
    """Nodes that left the cluster during the run (their jobs were sent again elsewhere)."""

    declined: int = 0
    """Times a worker declined a job because its node was short of memory (the job was sent again)."""

    paused: int = 0
    """Workers declining jobs right now."""

    warming: int = 0
    """Workers opening their editors before their first job."""


class Scheduler(Generic[J]):
    """Runs jobs on a worker pool and hands every finished attempt to ``on_result``."""

    def __init__(
        self,
        pool: WorkerPool,
        payloads: dict[str, ray.ObjectRef],
        *,
        timeout_s: float,
        retries: int,
        on_result: Callable[[J, JobResult], None],
        sends: Callable[[J, int, float], WorkerJob],
        max_in_flight: int | None = None,
        budget_usd: float | None = None,
        spent_usd: float = 0.0,
        open_editors: bool = True,
        calls_models: bool = False,
        watcher: SchedulerWatcher[J] | None = None,
        unplaced_hold_s: float = UNPLACED_HOLD_S,
    ) -> None:
        """``spent_usd`` is what earlier runs of the sweep spent; it counts against ``budget_usd``;
        ``open_editors``: workers open their editors ahead of their first job (False when no job needs one);
        ``calls_models``: workers import LiteLLM meanwhile (some job calls a model);
        ``watcher`` hears each attempt start and end; ``unplaced_hold_s``: see ``UNPLACED_HOLD_S``."""
        self.pool = pool
        self.payloads = payloads
        self.timeout_s = timeout_s
        self.retries = retries
        self.on_result = on_result
        self.sends = sends
        """What a worker is sent for an attempt of a job within a timeout (for a sweep: ``sweep.worker_job``)."""
        self.capacity = pool.capacity(max_in_flight)
        self.stats = SchedulerStats()
        self.budget_usd = budget_usd
        self.spent_usd = spent_usd
        self.open_editors = open_editors
        self.calls_models = calls_models
        self.watcher = watcher
        self.unplaced_hold_s = unplaced_hold_s
        self._flights: dict[ray.ObjectRef, _Flight[J]] = {}
        self._load = [0] * len(pool)
        self._down: dict[int, _Down] = {}
        self._paused: dict[int, ray.ObjectRef] = {}
        """Workers whose node is short of memory, and the call that answers once it has enough again."""
        self.nodes = NodeWatch()
        for worker, handle in enumerate(pool.handles):
            self.nodes.locate(worker, handle.info.remote())

    def run(self, jobs: Iterable[tuple[J, int]]) -> None:
        """Run each (job, first attempt) to a final outcome or until its retries are spent."""
        queue: deque[tuple[J, int]] = deque(jobs)
        first = {job.job_id: attempt for job, attempt in queue}
        if self.open_editors or self.calls_models:
            self._warm(len(queue))
        while queue or self._flights:
            self._check_nodes()
            self._probe_down()
            self._probe_paused()
            while queue and len(self._flights) < self.capacity and not self.over_budget:
                worker = self._free_worker()
                if worker is None:
                    break
                self._submit(worker, *queue.popleft())
            if not self._flights:
                if self.over_budget:  # what is queued stays unstarted
                    break
                # Every worker is restarting, opening its editors or short of memory: wait for one of them.
                probes = [down.probe for down in self._down.values() if not down.warmed] + list(self._paused.values())
                ray.wait(probes, timeout=WAIT_SLICE_S)
                continue
            for flight, result in self._collect():
                if result is None:  # its worker was restarted because of another job
                    queue.appendleft((flight.job, flight.attempt))
                    continue
                if isinstance(result, Refusal):  # not started: the same attempt, later or elsewhere
                    queue.appendleft((flight.job, flight.attempt))
                    self._pause(flight.worker)
                    continue
                retry = (
                    result.outcome == "error"
                    and result.error_class not in PERMANENT_ERRORS
                    and result.attempt - first[flight.job.job_id] < self.retries
                )
                self._record(flight.job, result, final=not retry)
                if retry:
                    queue.append((flight.job, result.attempt + 1))
        self.stats.not_started += len({job.job_id for job, _ in queue})

    @property
    def settled(self) -> bool:
        """No job is running on any worker (a run that ended normally; see ``WorkerPool.close``)."""
        return not self._flights

    def _warm(self, jobs: int) -> None:
        """Have every idle worker open the editors for its share of ``jobs`` (and import LiteLLM, when jobs call
        models) before it gets one; a worker the pool warmed ahead for these jobs goes on with that call."""
        idle = [worker for worker in range(len(self.pool)) if worker not in self._down and self._load[worker] == 0]
        calls = self.pool.warm(idle, jobs, self.capacity, self.open_editors, self.calls_models)
        for worker, warming in calls.items():
            self._down[worker] = _Down(warming, time.monotonic(), True)
        self.stats.warming = sum(down.warming for down in self._down.values())

    @property
    def over_budget(self) -> bool:
        return self.budget_usd is not None and self.spent_usd + self.stats.cost_usd >= self.budget_usd

    def _free_worker(self) -> int | None:
        """The least loaded worker that is up and has a page free."""
        free = [
            w
            for w in range(len(self._load))
            if w not in self._down and w not in self._paused and self._load[w] < self.pool.pages
        ]
        return min(free, key=self._load.__getitem__, default=None)

    def _mark_down(self, worker: int) -> None:
        if worker not in self._down:
            self._down[worker] = _Down(self.pool.handles[worker].info.remote(), time.monotonic())

    def _probe_down(self) -> None:
        """Take back the workers that answer again.

        One still failing past the episode timeout is taken back anyway: its jobs then fail and
        are recorded, as for a worker that is gone for good.
        """
        for worker, down in list(self._down.items()):
            if down.warmed:
                continue
            ready, _ = ray.wait([down.probe], timeout=0)
            if not ready:
                continue
            try:
                answer = ray.get(down.probe)
            except RayError:
                if time.monotonic() - down.since < self.timeout_s:
                    down.probe = self.pool.handles[worker].info.remote()
                    continue
                self.nodes.locate(worker, self.pool.handles[worker].info.remote())  # taken back unheard: ask again
            else:
                if isinstance(answer, WorkerInfo):  # back after a restart, perhaps on another node
                    self.nodes.locate(worker, answer)
            if down.warming:
                down.warmed = True
            else:
                del self._down[worker]
        self._start_warmed()
        self.stats.warming = sum(down.warming and not down.warmed for down in self._down.values())

    def _start_warmed(self) -> None:
        """Take back the workers that have opened their editors, once no other worker of their node still opens
        its own. One that has not said where it is yet (still starting) may be on any node, for
        ``UNPLACED_HOLD_S``: one Ray has not placed (the cluster's browser slots are taken) holds no one longer;
        one opening for longer than the episode timeout no longer counts either. One that has opened its editors
        but whose node is unknown (it died before it said) waits while any worker opens."""
        now = time.monotonic()
        opening: set[str | None] = set()
        for worker, down in self._down.items():
            if down.warming and not down.warmed and now - down.since < self.timeout_s:
                node = self.nodes.node_of(worker)
                if node is not None or now - down.since < self.unplaced_hold_s:
                    opening.add(node)
        for worker, down in list(self._down.items()):
            if not down.warmed:
                continue
            node = self.nodes.node_of(worker)  # None (unknown or unplaced) may be any node
            if not opening or (node is not None and None not in opening and node not in opening):
                del self._down[worker]

    def _check_nodes(self, force: bool = False) -> None:
        """Say which nodes left the cluster since the last look."""
        for node in self.nodes.check(force):
            self.stats.nodes_lost += 1
            if self.watcher is not None:
                self.watcher.node_lost(node)

    def _pause(self, worker: int) -> None:
        self.stats.declined += 1
        if worker not in self._paused:
            self._paused[worker] = self.pool.handles[worker].wait_admitting.remote(ADMISSION_WAIT_S)
        self.stats.paused = len(self._paused)

    def _probe_paused(self) -> None:
        """Take back the workers whose node has memory again (and those that died meanwhile, as down)."""
        for worker, probe in list(self._paused.items()):
            ready, _ = ray.wait([probe], timeout=0)
            if not ready:
                continue
            try:
                load: WorkerLoad = ray.get(probe)
            except RayError:
                del self._paused[worker]
                self._mark_down(worker)
                continue
            if load.admits:
                del self._paused[worker]
            else:
                self._paused[worker] = self.pool.handles[worker].wait_admitting.remote(ADMISSION_WAIT_S)
        self.stats.paused = len(self._paused)

    def _submit(self, worker: int, job: J, attempt: int) -> None:
        handle = self.pool.handles[worker]
        ref = handle.run.remote(self.sends(job, attempt, self.timeout_s), self.payloads[job.task_id])
        deadline = time.monotonic() + self.timeout_s + DEADLINE_GRACE_S
        self._flights[ref] = _Flight(job, attempt, worker, deadline, sent_at=time.time())
        self._load[worker] += 1
        self.stats.submitted += 1
        self.stats.in_flight = len(self._flights)
        if self.watcher is not None:
            self.watcher.started(job, attempt, worker)

    def _collect(self) -> list[tuple[_Flight[J], JobResult | Refusal | None]]:
        """Finished attempts (``None`` for a job to re-send as the same attempt), and declined jobs."""
        refs = list(self._flights)
        ready, _ = ray.wait(refs, num_returns=1, timeout=WAIT_SLICE_S)
        if ready:
            ready, _ = ray.wait(refs, num_returns=len(refs), timeout=0)
        finished: list[tuple[_Flight[J], JobResult | Refusal | None]] = []
        for ref in ready:
            flight = self._flights.pop(ref)
            self._load[flight.worker] -= 1
            finished.append((flight, self._result(ref, flight)))
        finished.extend(self._overdue())
        self.stats.in_flight = len(self._flights)
        return finished

    def _result(self, ref: ray.ObjectRef, flight: _Flight[J]) -> JobResult | Refusal | None:
        try:
            return ray.get(ref, timeout=60)
        except RayActorError as exc:
            self._mark_down(flight.worker)
            if flight.collateral:
                return None
            self._check_nodes(force=True)
            node = self.nodes.lost_with(flight.worker)
            if node is not None:
                message = f"the worker's node {node.name} left the cluster during the episode: {node.reason}"
            else:
                message = f"the worker died during the episode: {_first_line(exc)}"
            return self._lost(flight, "worker_died", message)
        except (RayError, GetTimeoutError) as exc:
            return self._lost(flight, "internal_error", f"{type(exc).__name__}: {_first_line(exc)}")

    def _overdue(self) -> list[tuple[_Flight[J], JobResult | None]]:
        now = time.monotonic()
        overdue = [(ref, f) for ref, f in self._flights.items() if f.deadline < now and not f.collateral]
        finished: list[tuple[_Flight[J], JobResult | None]] = []
        for ref, flight in overdue:
            self._flights.pop(ref)
            self._load[flight.worker] -= 1
            for other in self._flights.values():
                if other.worker == flight.worker:
                    other.collateral = True
            self.pool.restart(flight.worker)
            self._mark_down(flight.worker)
            self.stats.restarts += 1
            message = f"no answer {self.timeout_s + DEADLINE_GRACE_S:g} s after the episode started; worker restarted"
            finished.append((flight, self._lost(flight, "episode_timeout", message)))
        return finished

    def _lost(self, flight: _Flight[J], error_class: ErrorClass, message: str) -> JobResult:
        """The result of an attempt whose worker never answered, stamped with the times the driver saw."""
        result = JobResult.errored(self.sends(flight.job, flight.attempt, self.timeout_s), error_class, message)
        now = time.time()
        timings = result.timings.model_copy(update={"total_s": now - flight.sent_at})
        return result.model_copy(update={"started_at": flight.sent_at, "finished_at": now, "timings": timings})

    def _record(self, job: J, result: JobResult, *, final: bool) -> None:
        self.stats.attempts += 1
        if final:
            self.stats.outcomes[result.outcome] += 1
        else:
            self.stats.retried += 1
        self.stats.cost_usd += result.cost_usd
        self.on_result(job, result)
        if self.watcher is not None:
            self.watcher.finished(job, result, retried=not final)


def _first_line(exc: BaseException) -> str:
    return (str(exc).strip().splitlines() or [type(exc).__name__])[0][:500]
