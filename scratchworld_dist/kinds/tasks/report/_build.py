"""Building a ``RunReport`` from run directories: load, check, deduplicate, group, summarize.

A job can have several attempt rows (retries, resumes, a double delivery by Ray), so every
count goes through ``effective_rows``: one row per job, across all merged runs.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Iterable, Sequence
from pathlib import Path

from scratchworld_dist.kinds.tasks.report._stability_section import stability_section
from scratchworld_dist.kinds.tasks.report._summary import (
    CATEGORIES,
    DETERMINATE,
    ErrorCount,
    RunInfo,
    RunReport,
    ordered_categories,
    summarize,
)
from scratchworld_dist.reports import LoadedRun, load_runs
from scratchworld_dist.results import JobRow, RunManifest, effective_rows
from scratchworld_dist.sweep import stored_section

_Group = tuple[str, str, str]
"""(agent, model, mode): what one table row stands for."""


def build_report(run_dirs: Sequence[Path], *, force: bool = False) -> RunReport:
    """Merge the results of ``run_dirs`` into one report.

    Raises ``RunDirError`` for a directory that is not a run or has no results, and for runs
    of different suites or harnesses unless ``force`` (then the report carries a warning).
    """
    runs, warnings = load_runs(run_dirs, force=force)
    return report_of(runs, warnings)


def report_of(runs: Sequence[LoadedRun], warnings: list[str]) -> RunReport:
    """The report of runs already loaded and checked for merging (``warnings``: those of the check)."""
    warnings = [*warnings]
    warnings += [
        f"{run.name}: {run.stale_rows} row(s) from an older suite (suite hash differs) excluded"
        for run in runs
        if run.stale_rows
    ]
    shared = _jobs_in_several_runs(runs)
    if shared:
        warnings.append(f"{shared} job(s) appear in more than one run; each is counted once")

    attempts = [row for run in runs for row in run.rows]
    effective = list(effective_rows(attempts))
    groups: dict[_Group, list[JobRow]] = defaultdict(list)
    for row in effective:
        groups[(row.agent, row.model, row.mode)].append(row)
    missing = _missing_per_group(runs)
    rows = [summarize(*group, members, missing.get(group)) for group, members in groups.items()]
    rows.sort(key=lambda r: (r.mode, r.label))
    return RunReport(
        runs=[_run_info(run) for run in runs],
        warnings=warnings,
        categories=ordered_categories({r.category for r in effective} | set(CATEGORIES)),
        rows=rows,
        errors=_error_counts(attempts, effective),
        recovered_jobs=_recovered(attempts, effective),
        stability=stability_section(runs, effective),
    )


def _run_info(run: LoadedRun) -> RunInfo:
    effective = list(effective_rows(run.rows))
    decided = sum(r.outcome in DETERMINATE for r in effective)
    distinct = _distinct_attempts(run.rows)
    return RunInfo(
        path=str(run.path),
        run_name=run.manifest.run_name,
        suite_name=run.manifest.suite.name,
        suite_hash=run.manifest.suite.hash,
        harness=run.manifest.harness.digest if run.manifest.harness else "-",
        planned_jobs=run.manifest.planned_jobs,
        recorded_jobs=len(effective),
        determinate=decided,
        errors=len(effective) - decided,
        missing=max(run.manifest.planned_jobs - len(effective), 0),
        stale_rows=run.stale_rows,
        attempts=len(distinct),
        attempts_cost_usd=sum(r.cost_usd for r in distinct),
        budget_stop=run.manifest.sessions[-1].budget_stop if run.manifest.sessions else None,
        tags=run.manifest.tags or None,
    )


def _missing_per_group(runs: Sequence[LoadedRun]) -> dict[_Group, int | None]:
    """Planned-but-unrecorded jobs per group, summed over the runs the group appears in."""
    missing: dict[_Group, int | None] = {}
    for run in runs:
        planned = jobs_per_group(run.manifest)
        seen: dict[_Group, set[str]] = defaultdict(set)
        for row in run.rows:
            seen[(row.agent, row.model, row.mode)].add(row.job_id)
        for group, jobs in seen.items():
            known = missing.get(group, 0)
            if planned is None or known is None:
                missing[group] = None
            else:
                missing[group] = known + max(planned - len(jobs), 0)
    return missing


def jobs_per_group(manifest: RunManifest) -> int | None:
    """Planned jobs of each agent/model and mode (tasks x seeds), when the manifest's config says.

    The sweep plans models x modes x tasks x seeds; the product is checked against
    ``planned_jobs`` so that a config this cannot read yields ``None`` rather than a wrong count.
    """
    config = manifest.config
    seeds, modes, models = config.get("seeds"), stored_section(config, "tasks").get("modes"), config.get("models")
    if not isinstance(seeds, list) or not isinstance(modes, list) or not isinstance(models, list | None):
        return None
    per_group = manifest.suite.tasks * len(seeds)
    if max(len(models or []), 1) * len(modes) * per_group != manifest.planned_jobs:
        return None
    return per_group


def _error_counts(attempts: Iterable[JobRow], effective: Iterable[JobRow]) -> list[ErrorCount]:
    jobs = Counter(_error_class(r) for r in effective if r.outcome == "error")
    tries = Counter(_error_class(r) for r in _distinct_attempts(attempts) if r.outcome == "error")
    counts = [ErrorCount(error_class=c, jobs=jobs[c], attempts=tries[c]) for c in tries | jobs]
    return sorted(counts, key=lambda e: (-e.jobs, -e.attempts, e.error_class))


def _recovered(attempts: Iterable[JobRow], effective: Iterable[JobRow]) -> int:
    """Jobs whose verdict came from an attempt after one that ended in error."""
    first_error: dict[str, int] = {}
    for row in attempts:
        if row.outcome == "error":
            first_error[row.job_id] = min(row.attempt, first_error.get(row.job_id, row.attempt))
    return sum(r.outcome in DETERMINATE and r.attempt > first_error.get(r.job_id, r.attempt) for r in effective)


def _error_class(row: JobRow) -> str:
    return row.error_class or "unknown"


def _distinct_attempts(rows: Iterable[JobRow]) -> list[JobRow]:
    """One row per (job, attempt): an attempt committed twice happened once."""
    return list({(r.job_id, r.attempt): r for r in rows}.values())


def _jobs_in_several_runs(runs: Sequence[LoadedRun]) -> int:
    counts = Counter(job for run in runs for job in {r.job_id for r in run.rows})
    return sum(n > 1 for n in counts.values())
