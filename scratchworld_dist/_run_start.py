"""A sweep's start: its models' preflight, and meanwhile a private Ray and the workers that will run its jobs.

One after the other, a probe (LiteLLM's import and the model's first answer: 2-3 s, more for a slow model), a
private Ray's start (3-4 s) and the workers' (their browsers and editors: most of a start) left the cores idle
for as long as a probe waited on its model. So the preflight runs in a thread while this one starts the Ray,
then the workers, sized for every job still to run, which open their editors meanwhile. No job starts before
the preflight has answered, and a broken model still stops the sweep before anything is written: the workers
and the Ray go with ``ray_scope``.
"""

from __future__ import annotations

import contextlib
import os
import threading
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass
from functools import partial
from typing import NamedTuple, TypeVar

import ray

from scratchworld_dist.scheduling import (
    RayUnavailableError,
    WorkerPool,
    admitted_slots,
    broken_by_settings,
    exclusive,
    most_slots,
    pages_per_worker,
    ray_runtime,
    refuse_broken,
    run_preflight,
)
from scratchworld_dist.sweep import JobSpec, RunPlan
from workers.contract import MIB, NodeReport, Preflight

_T = TypeVar("_T")


@dataclass
class EarlyWorkers:
    """Workers started on a private Ray before the preflight answered, opening the editors of ``job_ids``."""

    pool: WorkerPool
    slots: int
    """The browser slots admission gave those jobs."""
    admission: list[str]
    """What admission said, to be said once the preflight has answered (before it, an error comes first)."""
    job_ids: list[str]

    def serve(self, jobs: list[JobSpec]) -> bool:
        """Whether these workers were started for exactly ``jobs`` (the preflight left none out)."""
        return [job.job_id for job in jobs] == self.job_ids


@dataclass
class SweepStart:
    preflight: Preflight | None
    ray_started: bool
    """A private Ray was started here (into ``ray_scope``)."""
    workers: EarlyWorkers | None


def start_beside_preflight(
    plan: RunPlan, jobs: list[JobSpec], nodes: list[NodeReport], ray_scope: contextlib.ExitStack
) -> SweepStart:
    """The preflight of ``jobs``' models; meanwhile, with a private Ray, that Ray (into ``ray_scope``: it offers
    the most slots admission may give) and the workers ``jobs`` need, opening their editors.

    The preflight runs alone on a cluster (Ray is joined already), with a Ray this process started itself, and
    when a model's settings alone show it broken (no call needed: the sweep stops at once, starting nothing).
    """
    config = plan.config
    if config.ray.address is not None or not jobs or ray.is_initialized() or broken_by_settings(plan, jobs):
        on_node = None if config.ray.address is None else nodes[0]  # a cluster: where the workers' environment is
        return SweepStart(run_preflight(plan, jobs, on_node), False, None)
    checking = _in_thread(partial(run_preflight, plan, jobs, None))
    try:
        ray_scope.enter_context(ray_runtime(None, most_slots(config.limits, os.cpu_count() or 1)))
    except RayUnavailableError:
        refuse_broken(checking.result(), skip_broken=False)  # a broken model is the first thing to say
        raise
    workers = None
    if not checking.done() or not _broken(checking.result()):
        said: list[str] = []
        slots = admitted_slots(config.limits, jobs, nodes[0].harness.digest, said.append)
        pool = sized_pool(plan, jobs, slots, os.cpu_count() or 1, local=True)
        needs = warm_needs(jobs)
        pool.warm_ahead(len(jobs), config.limits.max_in_flight, needs.open_editors, needs.calls_models)
        workers = EarlyWorkers(pool, slots, said, [job.job_id for job in jobs])
    return SweepStart(checking.result(), True, workers)


class WarmNeeds(NamedTuple):
    """What a sweep's workers do before their first job: open editors (some job needs one) and import LiteLLM
    (some job calls a model). The early workers and the scheduler must agree on it."""

    open_editors: bool
    calls_models: bool


def warm_needs(jobs: list[JobSpec]) -> WarmNeeds:
    return WarmNeeds(any(job.needs_browser for job in jobs), any(job.model is not None for job in jobs))


def sized_pool(plan: RunPlan, jobs: list[JobSpec], slots: int, cores: int, *, local: bool) -> WorkerPool:
    """The workers for ``jobs`` on ``slots`` browser slots: one page each when a person works on the jobs (on
    this machine), else ``pages_per_worker``; no more workers than the jobs run at once need."""
    limits = plan.config.limits
    pages = 1 if local and exclusive(jobs) else pages_per_worker(limits, slots, cores)
    at_once = min(len(jobs), limits.max_in_flight or len(jobs))
    return WorkerPool(slots, pages, plan.synthetic, limits.memory_reserve_mb * MIB, at_once)


def _broken(preflight: Preflight | None) -> bool:
    return preflight is not None and bool(preflight.broken)


def _in_thread(work: Callable[[], _T]) -> Future[_T]:
    """``work``'s outcome, run in a daemon thread (an interrupted sweep does not wait for it to end)."""
    outcome: Future[_T] = Future()

    def run() -> None:
        try:
            outcome.set_result(work())
        except BaseException as exc:  # handed to whoever waits on the outcome
            outcome.set_exception(exc)

    threading.Thread(target=run, name="preflight", daemon=True).start()
    return outcome
