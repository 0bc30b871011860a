"""``scratchworld plan``: what a sweep would run, before anything starts.

The plan is made exactly as ``run`` makes it (same config, overrides and suite), then compared with what
the run directory already decided. Model calls are an upper bound (each job's step budget); spend is
estimated from the mean cost per attempt of the same model, agent and mode in the run directory, when it
holds any (prices are LiteLLM's, as they were recorded), and left unknown otherwise.
"""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.results import JobRow, RunStore
from scratchworld_dist.sweep import JobSpec, Notice, SuiteInfo, SweepConfig, plan_run

Group = tuple[str, str, str]
"""(model, agent, mode): one line of the plan."""


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
    """At most this many model calls for the jobs to run (their step budgets; 0 for scripted agents)."""

    cost_usd: float | None
    """Estimated spend of the jobs to run (None: no earlier attempt of this line to estimate from)."""


class PlanPreview(BaseModel):
    """A sweep's job matrix against its run directory."""

    name: str
    benchmark: str
    run_dir: Path
    suite: SuiteInfo
    lines: list[PlanLine]
    notices: list[str]

    @property
    def to_run(self) -> int:
        return sum(line.to_run for line in self.lines)


def preview_plan(config: SweepConfig) -> PlanPreview:
    """Plan the sweep as ``run`` would and compare it with its run directory; nothing is started or written."""
    notices: list[str] = []
    notice: Notice = notices.append
    plan = plan_run(config, notice=notice)
    store = RunStore(config.run_dir())
    attempts = store.attempts()
    history = _mean_costs(store.job_rows() if attempts else [])
    groups: dict[Group, list[JobSpec]] = defaultdict(list)
    for job in plan.jobs:
        groups[(job.model_name, job.agent_label, job.mode)].append(job)
    lines = []
    for (model, agent, mode), jobs in groups.items():
        waiting = [job for job in jobs if not attempts.get(job.job_id, (0, False))[1]]
        calls = sum(_step_budget(job) for job in waiting if job.model is not None)
        mean = history.get((model, agent, mode))
        lines.append(
            PlanLine(
                model=model, agent=agent, mode=mode, jobs=len(jobs), decided=len(jobs) - len(waiting),
                to_run=len(waiting), model_calls=calls, cost_usd=None if mean is None else mean * len(waiting),
            )
        )  # fmt: skip
    return PlanPreview(
        name=config.name, benchmark=config.benchmark, run_dir=config.run_dir(), suite=plan.suite, lines=lines,
        notices=notices,
    )  # fmt: skip


def _step_budget(job: JobSpec) -> int:
    budget = job.body.columns().get("max_steps", 1)
    return budget if isinstance(budget, int) else 1


def _mean_costs(rows: list[JobRow]) -> dict[Group, float]:
    """Mean recorded cost per attempt of each line (every attempt: retries cost too)."""
    costs: dict[Group, list[float]] = defaultdict(list)
    for row in rows:
        costs[(row.model, row.agent, row.mode)].append(row.cost_usd)
    return {group: sum(values) / len(values) for group, values in costs.items()}


def render_preview(preview: PlanPreview) -> str:
    """The plan as plain text: one line per model, agent and mode, then the totals."""
    header = ("model", "agent", "mode", "jobs", "decided", "to run", "model calls (max)", "est. cost")
    rows = [
        (
            line.model, line.agent, line.mode, str(line.jobs), str(line.decided), str(line.to_run),
            str(line.model_calls), "unknown" if line.cost_usd is None else f"${line.cost_usd:.4f}",
        )
        for line in preview.lines
    ]  # fmt: skip
    widths = [max(len(cell) for cell in column) for column in zip(header, *rows, strict=True)]
    table = [
        "  ".join(cell.ljust(width) for cell, width in zip(row, widths, strict=True)).rstrip()
        for row in (header, *rows)
    ]
    suite = preview.suite
    costs = [line.cost_usd for line in preview.lines if line.to_run]
    known = [cost for cost in costs if cost is not None]
    total = (
        "unknown" if not known else f"${sum(known):.4f}" + (" (some lines unknown)" if len(known) < len(costs) else "")
    )
    return "\n".join(
        [
            f"{preview.name}: benchmark {preview.benchmark}, {suite.tasks} item(s) of {suite.name}"
            f" -> {preview.run_dir}",
            *preview.notices,
            *table,
            f"{preview.to_run} job(s) to run, {sum(line.decided for line in preview.lines)} already decided; "
            f"at most {sum(line.model_calls for line in preview.lines)} model call(s); estimated cost {total}",
        ]
    )
