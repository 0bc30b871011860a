"""A flake run's findings as a suite's known test stability (``--stability-out``), for the harness to read back."""

from __future__ import annotations

from collections.abc import Sequence
from datetime import UTC, datetime

from scratchworld_dist.kinds.tasks.flakes._analysis import FlakeReport, TestStability
from scratchworld_dist.suites import Task
from scratchworld_dist.suites._stability import SuiteStability, UnstableTest, scripts_digest


def _unstable_test(rows: list[TestStability]) -> UnstableTest:
    """One test over the projects in which it flipped (golden and initial are judged by the same test)."""
    flipped = [row for row in rows if not row.stable]
    bands = [f"{row.which} {row.lateness_band.describe()}" for row in flipped if row.lateness_band is not None]
    return UnstableTest(
        task_id=flipped[0].task_id,
        test=flipped[0].test,
        projects=[row.which for row in flipped],
        baseline=", ".join(f"{row.which} {row.baseline}" for row in flipped),
        flipped=sum(row.flipped for row in flipped),
        runs=sum(row.runs - 1 for row in flipped),
        flipped_by=list(dict.fromkeys(flip.axis for row in flipped for flip in row.flips)),
        flips=[f"{row.which}: {flip.label} → {flip.verdict}" for row in flipped for flip in row.flips],
        passes_at="; ".join(bands) or None,
    )


def suite_stability(report: FlakeReport, tasks: Sequence[Task], command: str) -> SuiteStability:
    """What ``report`` found about ``tasks`` (those it evaluated), with each task's scripts digested."""
    by_test: dict[tuple[str, str], list[TestStability]] = {}
    for row in report.tests:
        by_test.setdefault((row.task_id, row.test), []).append(row)
    checked = {run.task_id for run in report.runs}
    return SuiteStability(
        suite=report.suite,
        command=command,
        made_on=datetime.now(tz=UTC).date().isoformat(),
        profile=report.conditions.profile,
        clock=report.conditions.clock,
        render=report.conditions.render,
        page=report.conditions.page,
        axes=list(report.settings.axes),
        runs_per_axis=report.settings.runs,
        evaluations=report.evaluations,
        tests_checked=len(by_test),
        scripts={task.id: scripts_digest(task) for task in tasks if task.id in checked},
        unstable=[_unstable_test(rows) for rows in by_test.values() if not all(row.stable for row in rows)],
    )
