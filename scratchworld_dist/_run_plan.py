"""Planning a sweep: its config resolved by its kind (task episodes, drag tasks, perception items, a plugin's)
against its suite and a harness into the full job matrix, with each item's content read once."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from pydantic import BaseModel

from scratchworld_dist._console import make_console
from scratchworld_dist.kinds import Notice, job_kind
from scratchworld_dist.memory import JobItems
from scratchworld_dist.results import SuiteInfo
from scratchworld_dist.sweep import JobSpec, SweepConfig
from workers.contract import HarnessFingerprint, Mode
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint


class RunPlan(BaseModel):
    """A sweep resolved against its suite and this harness: the items' contents and the full job matrix."""

    config: SweepConfig
    harness: HarnessFingerprint
    suite: SuiteInfo
    contents: Sequence[Any]
    """Each selected item read into memory: its kind's content model (``task``, ``payload``, ``task_hash``)."""

    jobs: list[JobSpec]
    memory_sources: dict[tuple[str, Mode], list[JobItems]] = {}
    """Offline memory: the previous run's proposals per (model name, mode)."""


def plan_run(config: SweepConfig, harness: HarnessFingerprint | None = None, notice: Notice | None = None) -> RunPlan:
    """The sweep's jobs under ``harness`` (default: this machine's code, editor and browser); ``notice``
    hears what planning leaves out (default: standard error)."""
    if notice is None:
        console = make_console(stderr=True)
        notice = lambda message: console.print(message, markup=False)  # noqa: E731
    harness = kind_fingerprint(harness or harness_fingerprint(), config.benchmark)  # the core + this kind's code
    return job_kind(config.benchmark).plan(config, harness, notice)
