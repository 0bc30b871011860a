"""``compare --stable-only``: each job's verdict recomputed from its tests without those known to be unstable.

A test whose verdict flips with frame timing or phase says little about the agent, and a difference between
two systems that rests on such tests is noise. The tests left out are those either run's manifest marks
unstable (``suite.stability``), for every job of their task on both sides, so both are judged on the same
tests. A job that ran none of them keeps its verdict; one whose every test is left out has no verdict left
(outcome ``NO_STABLE_TEST``): it pairs with nothing, as an error would, and the output counts it.
"""

from __future__ import annotations

from collections.abc import Sequence

from pydantic import BaseModel

from scratchworld_dist.kinds.tasks.report._summary import DETERMINATE
from scratchworld_dist.reports import LoadedRun, tests_of_attempts
from scratchworld_dist.results import JobRow

NO_STABLE_TEST = "no stable test"
"""The outcome of a job all of whose tests were left out: not a verdict, so it is left out of every rate."""


class StableSide(BaseModel):
    """What leaving the unstable tests out did to one compared system's jobs."""

    label: str
    changed: int
    """Jobs whose verdict changed (a failure that rested on unstable tests alone now passes)."""

    without_test: int
    """Jobs whose every test was left out: no verdict is left (they pair with nothing)."""

    kept: int
    """Jobs of a task with unstable tests whose test rows the run lacks: their recorded verdict counts."""


class StableOnly(BaseModel):
    """``--stable-only``: the tests left out and what that did to each system's verdicts."""

    left_out: dict[str, list[str]]
    """Task id → the tests left out (marked unstable by any compared run)."""

    sides: list[StableSide]
    runs_without: list[str]
    """Compared runs that carry no stability data: tests unstable there are not known."""


def left_out_tests(runs: Sequence[LoadedRun]) -> dict[str, list[str]]:
    """The tests any of ``runs`` marks unstable, by task (sorted)."""
    found: dict[str, set[str]] = {}
    for run in runs:
        marks = run.manifest.suite.stability
        for task_id, tests in (marks.unstable if marks is not None else {}).items():
            found.setdefault(task_id, set()).update(tests)
    return {task_id: sorted(tests) for task_id, tests in sorted(found.items()) if tests}


def stable_verdicts(
    run: LoadedRun, rows: Sequence[JobRow], left_out: dict[str, list[str]], label: str
) -> tuple[list[JobRow], StableSide]:
    """``rows`` (effective rows of ``run``) with the verdicts of jobs that ran a left-out test recomputed from
    their other tests: outcome, tests passed and total, PSR. Errors, and failures of a project that broke the
    evaluation script (``eval_error_kind``), stay as they are."""
    touched = {
        (row.job_id, row.attempt)
        for row in rows
        if row.task_id in left_out and row.outcome in DETERMINATE and row.eval_error_kind is None
    }
    side = StableSide(label=label, changed=0, without_test=0, kept=0)
    if not touched:
        return list(rows), side
    tests = tests_of_attempts([run.path], touched)
    recomputed = []
    for row in rows:
        key = (row.job_id, row.attempt)
        if key not in touched:
            recomputed.append(row)
            continue
        recorded = tests.get(key, [])
        remaining = [t for t in recorded if t.name not in left_out[row.task_id]]
        if not recorded:
            side.kept += 1
            recomputed.append(row)
        elif len(remaining) == len(recorded):  # it ran none of the tests left out
            recomputed.append(row)
        elif not remaining:
            side.without_test += 1
            update = {"outcome": NO_STABLE_TEST, "tests_passed": 0, "tests_total": 0, "psr": None}
            recomputed.append(row.model_copy(update=update))
        else:
            passed = sum(t.passed for t in remaining)
            outcome = "passed" if passed == len(remaining) else "failed"
            side.changed += outcome != row.outcome
            update = {"outcome": outcome, "tests_passed": passed, "tests_total": len(remaining)}
            recomputed.append(row.model_copy(update=update | {"psr": passed / len(remaining)}))
    return recomputed, side


def stable_only_note(runs: Sequence[LoadedRun], left_out: dict[str, list[str]], sides: list[StableSide]) -> StableOnly:
    """The comparison's (or ranking's) record of what ``--stable-only`` did."""
    without = [run.name for run in runs if run.manifest.suite.stability is None]
    return StableOnly(left_out=left_out, sides=sides, runs_without=list(dict.fromkeys(without)))


def stable_only_text(stable: StableOnly) -> str:
    """One paragraph for people: which tests were left out, and how many verdicts that changed per system."""
    if not stable.left_out:
        text = "Stable tests only (--stable-only): no compared run marks any test unstable; nothing was left out."
    else:
        tests = "; ".join(f"{task}: {', '.join(map(repr, names))}" for task, names in stable.left_out.items())
        text = (
            "Stable tests only (--stable-only): each job's verdict and PSR are recomputed from its tests without "
            f"those known to be unstable in any compared run, left out for both sides: {tests}."
        )
        for side in stable.sides:
            text += f" {side.label}: {side.changed} verdict(s) changed"
            if side.without_test:
                text += f", {side.without_test} job(s) left with no test (no verdict: left out like errors)"
            if side.kept:
                text += f", {side.kept} job(s) kept their recorded verdict (their test rows are missing)"
            text += "."
    if stable.runs_without:
        text += f" Runs without stability data (their unstable tests are not known): {', '.join(stable.runs_without)}."
    return text
