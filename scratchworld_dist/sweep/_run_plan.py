"""Planning a sweep: its config resolved by its kind (task episodes, drag tasks, perception items, a plugin's)
against its suite and a harness into the full job matrix, with each item's content read once.

``KindPlanning`` is what planning asks of a kind: its items read and its job matrix (``plan``), and what a worker
is sent for one attempt of one of its jobs (``worker_job``).
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from typing import Protocol, runtime_checkable

from pydantic import BaseModel, InstanceOf

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.memory import JobItems
from scratchworld_dist.suites import StabilityMarks
from scratchworld_dist.sweep._config import KindConfig, SweepConfig
from scratchworld_dist.sweep._former_keys import Notice, stderr_notice
from scratchworld_dist.sweep._plan import JobSpec
from scratchworld_dist.sweep._step_tokens import DEFAULT_RATES, TokenRates
from workers.contract import HarnessFingerprint, MemorySettings, Mode, SyntheticEpisodes, WorkerJob
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint


class SuiteInfo(BaseModel):
    """The suite a run's items come from, as its manifest and reports name it."""

    name: str
    kind: str
    """The suite's layout (``native``, ``upstream``...)."""

    root: str
    hash: str
    """Hash of the selected tasks' contents; runs with different hashes are not comparable."""

    tasks: int
    stability: StabilityMarks | None = None
    """The suite's known test stability for the selected tasks when the run was planned (None: it has none,
    and in older runs); not part of the hash, since it changes no verdict."""


class PlannedItem(Protocol):
    @property
    def id(self) -> str: ...


@runtime_checkable
class ItemContent(Protocol):
    """One selected item read into memory, as its kind holds it (``TaskContent``, ``DragContent``...): the core
    sends each worker that runs one of its jobs the payload, once, by the item's id."""

    @property
    def task(self) -> PlannedItem: ...

    @property
    def payload(self) -> BaseModel: ...

    @property
    def task_hash(self) -> str: ...


class RunPlan(BaseModel):
    """A sweep resolved against its suite and this harness: the items' contents and the full job matrix."""

    config: SweepConfig
    harness: HarnessFingerprint
    suite: SuiteInfo
    contents: Sequence[InstanceOf[ItemContent]]
    """Each selected item read into memory: its kind's content model."""

    jobs: list[JobSpec]
    memory: MemorySettings | None = None
    """Memory shared across the jobs (a learning agent's): the run keeps it in a service of its own."""

    memory_sources: dict[tuple[str, Mode], list[JobItems]] = {}
    """Offline memory: the previous run's proposals per (model name, mode)."""

    synthetic: SyntheticEpisodes | None = None
    """Browserless stand-ins for the jobs of the tasks it covers: the workers run those instead, calling no model."""


class KindPlanning(KindConfig):
    """The planning facet of a kind: the sweep's items and jobs, and what workers are sent for them."""

    def plan(self, config: SweepConfig, harness: HarnessFingerprint, notice: Notice) -> RunPlan:
        """The sweep's items read once and its job matrix, under ``harness``."""
        raise NotImplementedError(f"benchmark {self.name} plans no jobs")

    def worker_job(self, job: JobSpec, attempt: int, timeout_s: float) -> WorkerJob:
        """What a worker is sent for one attempt of ``job``."""
        raise NotImplementedError(f"benchmark {self.name} sends workers no jobs")

    def token_rates(self, mode: str) -> TokenRates:
        """The tokens a job of ``mode`` is taken to use when no earlier run measured them (``plan``'s estimate);
        default: one step of a screenshot and a question (``DEFAULT_RATES``)."""
        return DEFAULT_RATES


def plan_run(config: SweepConfig, harness: HarnessFingerprint | None = None, notice: Notice | None = None) -> RunPlan:
    """The sweep's jobs under ``harness`` (default: this machine's code, editor and browser); ``notice``
    hears what planning leaves out (default: standard error)."""
    notice = notice or stderr_notice
    harness = kind_fingerprint(harness or harness_fingerprint(), config.benchmark)  # the core + this kind's code
    plan = job_kind(config.benchmark, KindPlanning).plan(config, harness, notice)
    selection = config.tasks
    if selection.limit is None:
        return plan
    if selection.sample == "random":
        return sampled_items(plan, selection.limit, selection.sample_seed)
    return first_items(plan, selection.limit)


def first_items(plan: RunPlan, limit: int) -> RunPlan:
    """The plan cut to its first ``limit`` items (``tasks.limit``), whatever its kind: their contents and jobs."""
    return _kept_items(plan, list(plan.contents[:limit]))


def sampled_items(plan: RunPlan, limit: int, seed: int) -> RunPlan:
    """The plan cut to ``limit`` items drawn at random with ``seed`` (``tasks.sample: random``), kept in suite
    order: the same seed over the same selection draws the same items, on any machine and Python."""
    order = sorted(range(len(plan.contents)), key=lambda i: plan.contents[i].task.id)  # independent of list order
    drawn = set(random.Random(seed).sample(order, min(limit, len(order))))
    return _kept_items(plan, [content for i, content in enumerate(plan.contents) if i in drawn])


def _kept_items(plan: RunPlan, kept: list[ItemContent]) -> RunPlan:
    ids = {content.task.id for content in kept}
    jobs = [job for job in plan.jobs if job.task_id in ids]
    suite = plan.suite.model_copy(update={"tasks": len(kept)})
    return plan.model_copy(update={"contents": kept, "jobs": jobs, "suite": suite})


def worker_job(job: JobSpec, attempt: int, timeout_s: float) -> WorkerJob:
    """What the worker is sent for ``attempt`` of ``job`` within ``timeout_s``, as the job's kind builds it."""
    return job_kind(job.benchmark, KindPlanning).worker_job(job, attempt, timeout_s)
