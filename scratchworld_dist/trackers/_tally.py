"""The run's metrics as its attempts end: SR, PSR, coverage and cost per mode and per mode and category.

Fed the run's events (``events.jsonl``'s ``job_finish``, ``job_retry``, ``job_error``), earlier sessions' first, so
a resumed run's metrics go on from where they were. A job counts by its last event: an error decided later is a
verdict, a verdict is never undone. SR is passed over decided jobs, PSR the mean fraction of tests passed over
them (errors are in neither, as in the report), coverage decided over planned, cost every attempt's spend.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

from scratchworld_dist.results import JobError, JobFinish, JobRetry, RunEvent


@dataclass
class _Group:
    planned: int = 0
    verdicts: dict[str, tuple[bool, float]] = field(default_factory=dict)
    """Decided jobs by id: (passed, PSR)."""

    cost_usd: float = 0.0


@dataclass(frozen=True)
class PlannedJob:
    """What a planned job's metrics are grouped by."""

    model: str
    mode: str
    category: str


class RunTally:
    """Metrics of the planned jobs, updated event by event."""

    def __init__(self, planned: dict[str, PlannedJob]) -> None:
        """``planned``: every job of the run by id (events of other jobs, from an older plan, are left out)."""
        self.planned = planned
        self.by_model = len({job.model for job in planned.values()}) > 1
        self.groups: dict[tuple[str, ...], _Group] = defaultdict(_Group)
        self.decided: set[str] = set()
        """The decided jobs' ids (how many: the step metrics are logged at)."""

        for job in planned.values():
            for key in self._keys(job):
                self.groups[key].planned += 1

    def _keys(self, job: PlannedJob) -> list[tuple[str, ...]]:
        head = (job.model, job.mode) if self.by_model else (job.mode,)
        return [head, (*head, job.category)]

    def hear(self, event: RunEvent) -> bool:
        """Count ``event``; whether it was an attempt's end (one that metrics may change with)."""
        if not isinstance(event, JobFinish | JobRetry | JobError):
            return False
        job = self.planned.get(event.job_id)
        if job is None:
            return False
        for key in self._keys(job):
            group = self.groups[key]
            group.cost_usd += event.cost_usd
            if isinstance(event, JobFinish):
                psr = event.tests_passed / event.tests_total if event.tests_total else float(event.outcome == "passed")
                group.verdicts[event.job_id] = (event.outcome == "passed", psr)
        if isinstance(event, JobFinish):
            self.decided.add(event.job_id)
        return True

    def metrics(self) -> dict[str, float]:
        """Every group's ``.../sr``, ``.../psr`` (once it has a verdict), ``.../coverage`` and ``.../cost_usd``."""
        found: dict[str, float] = {}
        for key, group in sorted(self.groups.items()):
            name = "/".join(key)
            verdicts = list(group.verdicts.values())
            if verdicts:
                found[f"{name}/sr"] = sum(passed for passed, _ in verdicts) / len(verdicts)
                found[f"{name}/psr"] = sum(psr for _, psr in verdicts) / len(verdicts)
            found[f"{name}/coverage"] = len(verdicts) / group.planned if group.planned else 0.0
            found[f"{name}/cost_usd"] = group.cost_usd
        found["decided"] = float(len(self.decided))
        return found
