"""Which models a sweep's jobs call: the sweep's ``models`` when its agents need one, and the helper models an
agent names (a grounding model...); scripted agents and synthetic episodes call none."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.sweep import JobSpec
from workers.contract import ModelSpec

if TYPE_CHECKING:
    from scratchworld_dist._run_plan import RunPlan


class ModelCalls:
    """The models each job of one sweep calls (a job of a scripted agent may carry a model label it never calls)."""

    def __init__(self, plan: RunPlan) -> None:
        config = plan.config
        kind = job_kind(config.benchmark)
        self.synthetic = plan.synthetic
        self.callable = [m.spec() for m in config.models] if kind.needs_model(config) else []
        self.callable += kind.helper_models(config.agent)

    def of(self, job: JobSpec) -> list[ModelSpec]:
        synthetic = self.synthetic
        if synthetic is not None and synthetic.covers(job.task_id):
            return []
        return [spec for spec in (job.model, *job.extra_models) if spec is not None and spec in self.callable]

    def over(self, jobs: Iterable[JobSpec]) -> list[ModelSpec]:
        """Every model ``jobs`` call, once each, in the order they first appear."""
        found: list[ModelSpec] = []
        for job in jobs:
            found += [spec for spec in self.of(job) if spec not in found]
        return found
