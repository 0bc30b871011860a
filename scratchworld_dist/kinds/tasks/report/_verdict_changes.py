"""Which verdicts a regrade changed: each regraded job against the source job it names."""

from __future__ import annotations

from collections.abc import Iterable

from pydantic import BaseModel

from scratchworld_dist.results import JobRow, effective_rows


class VerdictChange(BaseModel):
    """A job whose verdict differs between its source run and the regrade."""

    task_id: str
    seed: int
    mode: str
    before: str
    after: str
    tests_before: str
    tests_after: str


def verdict_changes(source: Iterable[JobRow], regraded: Iterable[JobRow]) -> tuple[list[VerdictChange], int]:
    """The regraded jobs (effective rows) whose outcome differs from their source's, and how many kept it.

    Jobs pair through ``regraded_from``; a regraded row whose source is not among ``source`` is left out.
    """
    by_id = {row.job_id: row for row in effective_rows(list(source))}
    changed: list[VerdictChange] = []
    unchanged = 0
    for row in sorted(effective_rows(list(regraded)), key=lambda r: (r.task_id, r.seed, r.mode, r.job_id)):
        before = by_id.get(row.regraded_from or "")
        if before is None:
            continue
        if before.outcome == row.outcome:
            unchanged += 1
            continue
        changed.append(
            VerdictChange(
                task_id=row.task_id,
                seed=row.seed,
                mode=row.mode,
                before=before.outcome,
                after=row.outcome,
                tests_before=f"{before.tests_passed}/{before.tests_total}",
                tests_after=f"{row.tests_passed}/{row.tests_total}",
            )
        )
    return changed, unchanged
