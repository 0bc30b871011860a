"""``scratchworld plan``: what a sweep would run, with which model settings, and what it may cost, before anything
starts.

The plan is made exactly as ``run`` makes it (same config, overrides and suite), then compared with what the run
directory already decided; a directory ``run`` would refuse (it holds another sweep) is said. Spend is estimated
and bounded per line (``scratchworld_dist._plan_cost``). ``PlanPreview`` is also ``plan --json``'s output.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError
from scratchworld_dist._plan_cost import LineCost, MeasuredRuns, ModelPrice, line_cost, model_price
from scratchworld_dist._sweep_manifest import checked_manifest
from scratchworld_dist.kinds import job_kind
from scratchworld_dist.results import RunStore
from scratchworld_dist.sweep import JobSpec, KindPlanning, Notice, SuiteInfo, SweepConfig, plan_run
from workers.contract import ModelSpec

Group = tuple[str, str, str]
"""(model, agent, mode): one line of the plan."""


class ModelSettings(BaseModel):
    """A model as the sweep's jobs call it: the settings its entry gives (None: LiteLLM's default is used)."""

    name: str
    model: str
    temperature: float | None
    max_tokens: int | None
    api_base: str | None
    api_base_env: str | None
    api_key_env: str | None
    params: dict[str, object]
    called: bool
    """Whether the agent calls it (a scripted agent's jobs only carry its name)."""

    probed: bool
    """Whether ``run`` calls it once before any job starts (``probe``; default: when it names ``api_key_env``)."""

    price: ModelPrice | None
    """LiteLLM's prices and limits of the model (None: not looked up, since no job calls it)."""


class PlanLine(BaseModel):
    """The jobs of one model, agent and mode."""

    model: str
    agent: str
    mode: str
    jobs: int
    decided: int
    """Jobs the run directory already holds a verdict for (a run skips them)."""

    to_run: int
    model_calls: int
    """At most this many model calls for the jobs to run: their step budgets, each job retried ``limits.retries``
    times (0 for agents that call no model)."""

    cost: LineCost
    """Estimated tokens and spend of the jobs to run, and its upper bound."""


class PlanTotals(BaseModel):
    """The lines summed; a cost is None when a line that runs jobs has none (the lines say why)."""

    to_run: int
    decided: int
    model_calls: int
    input_tokens: int
    output_tokens: int
    cost_usd: float | None
    known_cost_usd: float
    """The estimate over the lines that have one."""

    max_cost_usd: float | None


class PlanPreview(BaseModel):
    """A sweep's job matrix against its run directory (``plan --json``)."""

    name: str
    benchmark: str
    run_dir: Path
    suite: SuiteInfo
    tags: dict[str, str]
    models: list[ModelSettings]
    lines: list[PlanLine]
    totals: PlanTotals
    retries: int
    """``limits.retries``: the upper bound counts that many retries of every job."""

    refusal: str | None
    """Why ``run`` would refuse the run directory (it holds another sweep), without ``--force``."""

    notices: list[str]
    """What loading and planning noticed, and warnings (an agent that calls no model given models)."""

    @property
    def to_run(self) -> int:
        return self.totals.to_run


def preview_plan(
    config: SweepConfig, tokens_from: Sequence[Path] = (), notices: list[str] | None = None
) -> PlanPreview:
    """Plan the sweep as ``run`` would and compare it with its run directory; nothing is started or written.
    ``tokens_from``: earlier runs of the suite to measure tokens per step in; ``notices`` (those loading the config
    said) gain planning's."""
    notices = notices if notices is not None else []
    notice: Notice = notices.append
    plan = plan_run(config, notice=notice)
    kind = job_kind(config.benchmark, KindPlanning)
    calls_model = bool(config.models) and kind.needs_model(config)
    if config.models and not calls_model:
        notice(
            f"warning: agent {config.agent.display} calls no model: its jobs only carry the models' names "
            "(no model call, no cost); the models change their ids"
        )
    run_dir = config.run_dir()
    refusal = None
    try:
        checked_manifest(plan, run_dir, force=False, write_info=False)
    except RunDirError as exc:
        refusal = f"run would refuse this directory: {exc}"
    store = RunStore(run_dir)
    attempts = store.attempts() if run_dir.is_dir() else {}
    measured = MeasuredRuns(plan.suite.name, tokens_from, run_dir, notices)
    groups: dict[Group, list[JobSpec]] = defaultdict(list)
    for job in plan.jobs:
        groups[(job.model_name, job.agent_label, job.mode)].append(job)
    specs = [model.spec() for model in config.models]
    prices = {spec.name: model_price(spec) for spec in specs} if calls_model else {}
    retries = config.limits.retries
    lines = []
    for (model, agent, mode), jobs in groups.items():
        waiting = [job for job in jobs if not attempts.get(job.job_id, (0, False))[1]]
        spec = jobs[0].model if calls_model else None
        budgets = [_step_budget(job) for job in waiting] if spec is not None else []
        rates = None
        if spec is not None:
            rates = measured.rates(mode, spec) or kind.token_rates(mode)
        price = prices.get(spec.name) if spec is not None else None
        lines.append(
            PlanLine(
                model=model, agent=agent, mode=mode, jobs=len(jobs), decided=len(jobs) - len(waiting),
                to_run=len(waiting), model_calls=sum(budgets) * (1 + retries),
                cost=line_cost(budgets, spec, rates, retries, price),
            )
        )  # fmt: skip
    return PlanPreview(
        name=config.name, benchmark=config.benchmark, run_dir=run_dir, suite=plan.suite, tags=config.tags,
        models=[_settings(spec, config, calls_model, prices.get(spec.name)) for spec in specs], lines=lines,
        totals=_totals(lines), retries=retries, refusal=refusal, notices=notices,
    )  # fmt: skip


def _settings(spec: ModelSpec, config: SweepConfig, called: bool, price: ModelPrice | None) -> ModelSettings:
    probe = config.probe if config.probe is not None else any(m.api_key_env for m in config.models)
    return ModelSettings(
        name=spec.name, model=spec.model, temperature=spec.temperature, max_tokens=spec.max_tokens,
        api_base=spec.api_base, api_base_env=spec.api_base_env, api_key_env=spec.api_key_env,
        params=dict(spec.params), called=called, probed=called and probe, price=price,
    )  # fmt: skip


def _totals(lines: list[PlanLine]) -> PlanTotals:
    running = [line for line in lines if line.to_run]
    costs = [line.cost.cost_usd for line in running]
    bounds = [line.cost.max_cost_usd for line in running]
    known = sum(cost for cost in costs if cost is not None)
    return PlanTotals(
        to_run=sum(line.to_run for line in lines),
        decided=sum(line.decided for line in lines),
        model_calls=sum(line.model_calls for line in lines),
        input_tokens=sum(line.cost.input_tokens for line in lines),
        output_tokens=sum(line.cost.output_tokens for line in lines),
        cost_usd=known if all(cost is not None for cost in costs) else None,
        known_cost_usd=known,
        max_cost_usd=sum(b for b in bounds if b is not None) if all(b is not None for b in bounds) else None,
    )


def _step_budget(job: JobSpec) -> int:
    budget = job.body.columns().get("max_steps", 1)
    return budget if isinstance(budget, int) else 1
