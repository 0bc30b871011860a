"""What must hold after a chaos run, computed from the run directory's files and the sweep's plan alone.

Each check carries the figures behind its verdict, so a PASS can be read as well as a FAIL.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from pathlib import Path
from typing import get_args

from pydantic import BaseModel

from scratchworld_dist._run import RunPlan
from scratchworld_dist.kinds.tasks.report import build_report
from scratchworld_dist.results import JobRow, RunStore, effective_rows, read_manifest
from workers.contract import ErrorClass

VERDICTS = ("passed", "failed")


class Check(BaseModel):
    name: str
    ok: bool
    figures: str


def check_run(run_dir: Path, plan: RunPlan) -> list[Check]:
    rows = RunStore(run_dir).job_rows()
    return [
        _job_set(rows, plan),
        _no_duplicates(rows),
        _verdicts_agree(rows),
        _errors_classified(rows),
        _report_matches(run_dir, rows, plan),
    ]


def _job_set(rows: list[JobRow], plan: RunPlan) -> Check:
    planned = {job.job_id for job in plan.jobs}
    recorded = {row.job_id for row in rows}
    missing, foreign = planned - recorded, recorded - planned
    manifest = read_manifest(plan.config.run_dir())
    in_manifest = manifest.planned_jobs if manifest is not None else None
    ok = not missing and not foreign and in_manifest == len(planned)
    figures = (
        f"planned {len(planned)} (manifest {in_manifest}), jobs with rows {len(recorded)}, "
        f"missing {len(missing)}, foreign {len(foreign)}"
    )
    return Check(name="job ids in the results == the planned job set", ok=ok, figures=figures)


def _no_duplicates(rows: list[JobRow]) -> Check:
    counts = Counter((row.job_id, row.attempt) for row in rows)
    doubled = {key: n for key, n in counts.items() if n > 1}
    figures = f"{len(rows)} attempt rows, {len(counts)} distinct (job_id, attempt), {len(doubled)} duplicated"
    return Check(name="no duplicate (job_id, attempt) rows", ok=not doubled, figures=figures)


def _verdicts_agree(rows: list[JobRow]) -> Check:
    verdicts: dict[str, set[tuple[str, int, int]]] = defaultdict(set)
    counts: Counter[str] = Counter()
    for row in rows:
        if row.outcome in VERDICTS:
            verdicts[row.job_id].add((row.outcome, row.tests_passed, row.tests_total))
            counts[row.job_id] += 1
    disagree = [job for job, seen in verdicts.items() if len(seen) > 1]
    several = sum(n > 1 for n in counts.values())
    figures = f"{len(verdicts)} jobs with a verdict, {several} with several verdict rows, {len(disagree)} disagree"
    return Check(name="no job decided twice differently", ok=not disagree, figures=figures)


def _errors_classified(rows: list[JobRow]) -> Check:
    known = set(get_args(ErrorClass))
    errors = [row for row in rows if row.outcome == "error"]
    unknown = [row for row in errors if row.error_class not in known]
    silent = [row for row in errors if not (row.error_message or "").strip()]
    stray = [row for row in rows if row.outcome != "error" and row.error_class is not None]
    classes = Counter(row.error_class for row in errors)
    figures = (
        f"{len(errors)} error rows {dict(sorted(classes.items()))}; unknown class {len(unknown)}, "
        f"no message {len(silent)}, verdict rows with an error class {len(stray)}"
    )
    return Check(
        name="every error row classified, with a message", ok=not (unknown or silent or stray), figures=figures
    )


def _report_matches(run_dir: Path, rows: list[JobRow], plan: RunPlan) -> Check:
    """The report's per-group counts, error counts and run totals, recomputed from the rows."""
    report = build_report([run_dir])
    effective = list(effective_rows(rows))
    planned: dict[tuple[str, str, str], set[str]] = defaultdict(set)
    for job in plan.jobs:
        planned[(job.agent.display, job.model_name, job.body.mode)].add(job.job_id)
    mismatches: list[str] = []
    figures: list[str] = []
    for row in report.rows:
        group = [r for r in effective if (r.agent, r.model, r.mode) == (row.agent, row.model, row.mode)]
        passed = sum(r.outcome == "passed" for r in group)
        failed = sum(r.outcome == "failed" for r in group)
        errors = sum(r.outcome == "error" for r in group)
        missing = len(planned[(row.agent, row.model, row.mode)] - {r.job_id for r in group})
        coverage = (passed + failed) / (len(group) + missing) if group or missing else None
        direct = (len(group), passed, failed, errors, missing, coverage)
        reported = (row.jobs, row.passed, row.determinate - row.passed, row.errors, row.missing, row.coverage)
        if direct != reported:
            mismatches.append(f"{row.label}/{row.mode}: report {reported} != rows {direct}")
        figures.append(
            f"{row.label}/{row.mode}: jobs {row.jobs}, passed {row.passed}, failed {row.determinate - row.passed}, "
            f"errors {row.errors}, missing {row.missing}, coverage {row.coverage:.1%}"
        )
    attempts = {(r.job_id, r.attempt): r for r in rows}.values()
    direct_errors = {
        cls: (sum(r.error_class == cls for r in effective if r.outcome == "error"), n)
        for cls, n in Counter(r.error_class for r in attempts if r.outcome == "error").items()
    }
    reported_errors = {e.error_class: (e.jobs, e.attempts) for e in report.errors}
    if direct_errors != reported_errors:
        mismatches.append(f"errors by class: report {reported_errors} != rows {direct_errors}")
    (info,) = report.runs
    totals = (info.recorded_jobs, info.determinate, info.errors, info.attempts)
    direct_totals = (
        len(effective),
        sum(r.outcome in VERDICTS for r in effective),
        sum(r.outcome == "error" for r in effective),
        len(attempts),
    )
    if totals != direct_totals:
        mismatches.append(f"run totals: report {totals} != rows {direct_totals}")
    figures.append(f"error attempts by class (jobs, attempts): {reported_errors}")
    figures.extend(mismatches)
    return Check(name="the report's counts match the rows", ok=not mismatches, figures="; ".join(figures))
