"""The report as data: one row per agent/model and mode, plus what the runs hold and lack.

Every rate here counts determinate jobs only (outcome ``passed`` or ``failed``). A job that
ended in ``error`` has no verdict: counting it as a failure would blame the agent for the
infrastructure, so it is left out of SR and PSR and shows up under coverage and errors.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence

from pydantic import BaseModel

from scratchworld_dist.kinds.tasks.report._stability_section import StabilitySection
from scratchworld_dist.reports import (
    LaterFields,
    MeanInterval,
    mean_interval,
    mean_pass_at_k,
    mean_pass_hat_k,
    row_label,
)
from scratchworld_dist.results import JobRow

REPORT_VERSION = 1
"""Bumped on any incompatible change to the JSON form of ``RunReport``."""

CATEGORIES = ("create", "debug", "extend", "compute")
"""The benchmark's task categories, in the order of its main table."""

DETERMINATE = ("passed", "failed")


class CategoryStats(BaseModel):
    """Outcomes of one row's jobs in one task category."""

    determinate: int
    passed: int
    errors: int
    sr: float | None
    """``passed / determinate``; ``None`` when no job of the category has a verdict."""


class KEstimate(BaseModel):
    """pass@k or pass^k at one ``k``, averaged over tasks."""

    k: int
    value: float | None
    """``None`` when no task has ``k`` determinate attempts."""

    tasks: int
    """Tasks averaged: those with at least ``k`` determinate attempts (one per seed)."""


class SeedRate(BaseModel):
    """Success rate of one row within one seed."""

    seed: int
    determinate: int
    passed: int
    sr: float | None


class SeedStats(BaseModel):
    """Statistics across seeds; present only for rows with two or more seeds."""

    per_seed: list[SeedRate]
    sr: MeanInterval | None
    """Mean of the per-seed SRs with a 95% t interval (seeds without a verdict are left out)."""

    pass_at_k: list[KEstimate]
    """Chance that at least one of k attempts at a task passes, for k = 1..number of seeds."""

    pass_hat_k: list[KEstimate]
    """Chance that all k attempts at a task pass (pass^k), for k = 1..number of seeds."""


class ReportRow(BaseModel):
    """One agent/model in one mode: the benchmark's main table row."""

    label: str
    """``oracle``/``noop`` for scripted agents, the model label for ``llm``."""

    agent: str
    model: str
    mode: str
    jobs: int
    """Distinct jobs with a result (each counted once, at its effective attempt)."""

    determinate: int
    passed: int
    errors: int
    """Jobs whose effective outcome is ``error``: excluded from SR and PSR."""

    missing: int | None
    """Planned jobs of this row with no result at all; ``None`` when the manifests cannot tell."""

    coverage: float | None
    """``determinate / (jobs + missing)``, or ``determinate / jobs`` when ``missing`` is unknown."""

    sr: float | None
    """Success rate: ``passed / determinate``."""

    psr: float | None
    """Partial success rate: mean fraction of tests passed over determinate jobs."""

    categories: dict[str, CategoryStats]
    mean_steps: float | None
    """Mean agent steps over determinate jobs."""

    mean_agent_s: float | None = None
    """Mean seconds the agent acted per determinate job (its time per task: a person's on the wall clock)."""

    input_tokens: int
    output_tokens: int
    cost_usd: float
    """Spend of the effective attempts (error jobs included, retried attempts not)."""

    cost_per_success: float | None
    seeds: SeedStats | None
    llm_cache_hits: int | None = None
    """Model calls answered from the model cache (no request, no cost), over the jobs that ran with one;
    ``None`` when none did."""

    llm_cache_calls: int | None = None
    """All model calls of the jobs that ran with the model cache (what ``llm_cache_hits`` is out of)."""


class ErrorCount(BaseModel):
    """How often one error class occurred."""

    error_class: str
    jobs: int
    """Jobs whose effective outcome is an error of this class."""

    attempts: int
    """Error attempts of this class, including those of jobs a retry later decided."""


class RunInfo(LaterFields):
    """One run directory of the report and how complete it is."""

    later_fields = ("tags",)

    path: str
    run_name: str
    suite_name: str
    suite_hash: str
    harness: str
    """The run's harness fingerprint (``-`` for runs older than fingerprints)."""

    planned_jobs: int
    recorded_jobs: int
    """Distinct jobs of the current suite with at least one attempt."""

    determinate: int
    errors: int
    missing: int
    """``planned_jobs - recorded_jobs``: never run, lost, or still running."""

    stale_rows: int
    """Attempt rows from an older suite or harness (hash or fingerprint differs from the manifest): excluded."""

    attempts: int
    attempts_cost_usd: float
    """Spend of every attempt of the current suite, retries included."""

    budget_stop: str | None = None
    """Set when the latest session stopped starting jobs because the sweep's budget was spent."""

    tags: dict[str, str] | None = None
    """The run's labels (``run --tag key=value``); None (and left out of the JSON) when it has none."""


class RunReport(LaterFields):
    """A report over one or more run directories (the JSON output is its ``model_dump``)."""

    later_fields = ("stability",)

    version: int = REPORT_VERSION
    runs: list[RunInfo]
    warnings: list[str]
    categories: list[str]
    """Category columns, the benchmark's four first, then any others seen."""

    rows: list[ReportRow]
    """Sorted by mode, then label."""

    errors: list[ErrorCount]
    """Most frequent first."""

    recovered_jobs: int
    """Jobs with an error attempt whose later attempt got a verdict."""

    stability: StabilitySection | None = None
    """The runs' known test stability: tasks with unstable tests and the failed verdicts resting on them alone;
    None (and left out of the JSON) when no run carries stability data."""


def ordered_categories(seen: set[str]) -> list[str]:
    """The benchmark's categories in table order, then any others seen (alphabetical)."""
    return [c for c in CATEGORIES if c in seen] + sorted(seen - set(CATEGORIES))


def summarize(agent: str, model: str, mode: str, rows: Sequence[JobRow], missing: int | None) -> ReportRow:
    """One table row from the effective rows (one per job) of one agent/model and mode."""
    decided = [r for r in rows if r.outcome in DETERMINATE]
    passed = sum(r.outcome == "passed" for r in decided)
    psrs = [r.psr for r in decided if r.psr is not None]
    planned = len(rows) + (missing or 0)
    cost = sum(r.cost_usd for r in rows)
    cached = [r for r in rows if r.llm_cache_hits is not None]
    return ReportRow(
        label=row_label(agent, model),
        agent=agent,
        model=model,
        mode=mode,
        jobs=len(rows),
        determinate=len(decided),
        passed=passed,
        errors=len(rows) - len(decided),
        missing=missing,
        coverage=len(decided) / planned if planned else None,
        sr=passed / len(decided) if decided else None,
        psr=sum(psrs) / len(psrs) if psrs else None,
        categories={c: _category(c, rows) for c in ordered_categories({r.category for r in rows})},
        mean_steps=sum(r.steps for r in decided) / len(decided) if decided else None,
        mean_agent_s=sum(r.agent_s for r in decided) / len(decided) if decided else None,
        input_tokens=sum(r.input_tokens for r in rows),
        output_tokens=sum(r.output_tokens for r in rows),
        cost_usd=cost,
        cost_per_success=cost / passed if passed else None,
        seeds=_seed_stats(rows),
        llm_cache_hits=sum(r.llm_cache_hits or 0 for r in cached) if cached else None,
        llm_cache_calls=sum(r.llm_calls for r in cached) if cached else None,
    )


def _category(category: str, rows: Sequence[JobRow]) -> CategoryStats:
    mine = [r for r in rows if r.category == category]
    decided = [r for r in mine if r.outcome in DETERMINATE]
    passed = sum(r.outcome == "passed" for r in decided)
    return CategoryStats(
        determinate=len(decided),
        passed=passed,
        errors=len(mine) - len(decided),
        sr=passed / len(decided) if decided else None,
    )


def _seed_stats(rows: Sequence[JobRow]) -> SeedStats | None:
    seeds = sorted({r.seed for r in rows})
    if len(seeds) < 2:
        return None
    per_seed = []
    for seed in seeds:
        decided = [r for r in rows if r.seed == seed and r.outcome in DETERMINATE]
        passed = sum(r.outcome == "passed" for r in decided)
        sr = passed / len(decided) if decided else None
        per_seed.append(SeedRate(seed=seed, determinate=len(decided), passed=passed, sr=sr))
    rates = [s.sr for s in per_seed if s.sr is not None]
    per_task: dict[str, list[bool]] = defaultdict(list)
    for row in rows:
        if row.outcome in DETERMINATE:
            per_task[row.task_id].append(row.outcome == "passed")
    counts = [(len(v), sum(v)) for v in per_task.values()]
    ks = range(1, len(seeds) + 1)
    return SeedStats(
        per_seed=per_seed,
        sr=mean_interval(rates) if rates else None,
        pass_at_k=[KEstimate(k=k, value=mean_pass_at_k(counts, k), tasks=_tasks_with(counts, k)) for k in ks],
        pass_hat_k=[KEstimate(k=k, value=mean_pass_hat_k(counts, k), tasks=_tasks_with(counts, k)) for k in ks],
    )


def _tasks_with(counts: Sequence[tuple[int, int]], k: int) -> int:
    return sum(n >= k for n, _ in counts)
