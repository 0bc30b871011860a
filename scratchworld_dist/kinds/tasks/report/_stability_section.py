"""What a report says of the runs' known test stability: which tasks have unstable tests, and which failed
verdicts rest on them alone.

A run keeps the suite's known stability in its manifest (``suite.stability``) and marks each test row
(``tests.unstable``); a failed job whose every failed test is unstable would pass without those tests, so
its verdict says more about frame timing than about the agent. Runs without the data get no section.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from pydantic import BaseModel

from scratchworld_dist.reports import LoadedRun, tests_of_attempts
from scratchworld_dist.results import JobRow


class UnstableTask(BaseModel):
    """One task with tests known to be unstable, and its jobs' verdicts that rest on them."""

    task_id: str
    tests: dict[str, str]
    """Each unstable test by name, with its note (what changes it and where it passes)."""

    determinate: int
    """The task's jobs with a verdict (each job once, at its effective attempt)."""

    failed: int
    failed_on_unstable_only: int
    """Failed jobs whose every failed test is unstable: without those tests they would pass."""


class StabilitySection(BaseModel):
    """The runs' known test stability (from their manifests) as the report states it."""

    sources: list[str]
    """Each stability file the runs' marks came from, with the date it was made."""

    tasks: int
    """The tasks the runs selected."""

    checked: int
    """Of those, the tasks the data covers (their scripts unchanged since it was made)."""

    unstable_tasks: list[UnstableTask]
    failed_on_unstable_only: int
    """Failed jobs, over all tasks, whose every failed test is unstable."""

    runs_without: list[str]
    """Runs merged into the report that carry no stability data (their tests are not marked)."""


def stability_section(runs: Sequence[LoadedRun], effective: Iterable[JobRow]) -> StabilitySection | None:
    """The section's data, or None when no run carries stability data (the report then prints as before)."""
    marked = [run for run in runs if run.manifest.suite.stability is not None]
    if not marked:
        return None
    notes: dict[str, dict[str, str]] = {}
    checked: set[str] = set()
    sources: list[str] = []
    for run in marked:
        marks = run.manifest.suite.stability
        assert marks is not None  # marked runs have it
        checked.update(marks.checked)
        for task_id, tests in marks.unstable.items():
            notes.setdefault(task_id, {}).update(tests)
        source = f"{marks.source}, made {marks.made_on}"
        sources += [source] if source not in sources else []
    decided = [row for row in effective if row.outcome in ("passed", "failed")]  # as the report's DETERMINATE
    failed = [row for row in decided if row.outcome == "failed"]
    resting = _failed_on_unstable_only(marked, failed)
    tasks = [
        UnstableTask(
            task_id=task_id,
            tests=dict(sorted(notes[task_id].items())),
            determinate=sum(row.task_id == task_id for row in decided),
            failed=sum(row.task_id == task_id for row in failed),
            failed_on_unstable_only=sum(row.task_id == task_id for row in resting),
        )
        for task_id in sorted(notes)
        if notes[task_id]
    ]
    return StabilitySection(
        sources=sources,
        tasks=max(run.manifest.suite.tasks for run in marked),
        checked=len(checked),
        unstable_tasks=tasks,
        failed_on_unstable_only=len(resting),
        runs_without=[run.name for run in runs if run.manifest.suite.stability is None],
    )


def _failed_on_unstable_only(runs: Sequence[LoadedRun], failed: Sequence[JobRow]) -> list[JobRow]:
    """The failed jobs whose tests (at their effective attempt) failed only where marked unstable."""
    wanted = {(row.job_id, row.attempt) for row in failed}
    # Only runs with marks: an unmarked run's tests are never marked unstable.
    tests = tests_of_attempts((run.path for run in runs), wanted)
    resting = []
    for row in failed:
        failures = [t for t in tests.get((row.job_id, row.attempt), []) if not t.passed]
        if failures and all(t.unstable for t in failures):
            resting.append(row)
    return resting
