"""What a sweep's driver says as its jobs run: every attempt as an event in the run directory's ``events.jsonl``
(``scratchworld_dist.results._events``), and every error as a line in the log as it happens (a retry included),
so a run off a terminal shows its trouble before it ends."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any, Literal

from rich.console import Console

from scratchworld_dist.results import (
    EventLog,
    JobError,
    JobFinish,
    JobRetry,
    JobStart,
    NodeLost,
    RunEvent,
    SweepEnd,
)
from scratchworld_dist.scheduling import LostNode
from scratchworld_dist.sweep import JobSpec
from workers.contract import JobResult

MESSAGE_CHARS = 300
"""An error line quotes at most this much of the message (the rows keep it whole)."""


class SweepWatcher:
    """Hears the scheduler (``SchedulerWatcher``): writes each attempt's events and prints its errors; ``followers``
    hear every event it writes (the experiment trackers' feed, the job spans), and must return at once."""

    def __init__(
        self,
        events: EventLog,
        session: int,
        console: Console,
        say_errors: bool,
        followers: Sequence[Callable[[RunEvent], None]] = (),
    ) -> None:
        self.events = events
        self.followers = list(followers)
        self.session = session
        self.console = console
        self.say_errors = say_errors
        self.sent = 0
        self.retried = 0
        self.cost_usd = 0.0
        self.outcomes = {"passed": 0, "failed": 0, "error": 0}
        self.began = time.monotonic()

    def _write(self, event: JobStart | JobFinish | JobRetry | JobError | SweepEnd) -> None:
        self.events.write(event)
        for follow in self.followers:
            follow(event)

    def _job(self, job: JobSpec, attempt: int) -> dict[str, Any]:
        return {
            "session": self.session, "job_id": job.job_id, "task_id": job.task_id, "model": job.model_name,
            "agent": job.agent_label, "mode": job.mode, "seed": job.seed, "attempt": attempt,
        }  # fmt: skip

    def started(self, job: JobSpec, attempt: int, worker: int) -> None:
        self.sent += 1
        self._write(JobStart(**self._job(job, attempt), worker=worker))

    def finished(self, job: JobSpec, result: JobResult, *, retried: bool) -> None:
        self.cost_usd += result.cost_usd
        if retried:
            self.retried += 1
        else:
            self.outcomes[result.outcome] += 1
        fields = self._job(job, result.attempt)
        if result.outcome != "error":
            evaluation = result.evaluation
            self._write(
                JobFinish(
                    **fields, outcome=result.outcome, steps=len(result.steps),
                    tests_passed=evaluation.passed if evaluation is not None else 0,
                    tests_total=evaluation.total if evaluation is not None else 0,
                    input_tokens=result.input_tokens, output_tokens=result.output_tokens, cost_usd=result.cost_usd,
                    seconds=result.timings.total_s,
                )
            )  # fmt: skip
            return
        kind = JobRetry if retried else JobError
        error = {"error_class": result.error_class, "message": result.error_message, "cost_usd": result.cost_usd}
        self._write(kind(**fields, **error))
        if self.say_errors:
            message = " ".join((result.error_message or "").split())[:MESSAGE_CHARS]
            then = "; retrying" if retried else "; no retry left"
            self.console.print(
                f"error: {job.task_id} ({job.model_name}, {job.agent_label}, {job.mode}, seed {job.seed}) "
                f"attempt {result.attempt}: {result.error_class or 'error'}: {message}{then}",
                markup=False,
                highlight=False,
                soft_wrap=True,
            )

    def node_lost(self, node: LostNode) -> None:
        self.events.write(
            NodeLost(
                session=self.session, node_id=node.node_id, address=node.address, hostname=node.hostname,
                reason=node.reason, workers=list(node.workers),
            )
        )  # fmt: skip
        workers = f"worker(s) {', '.join(map(str, node.workers))}" if node.workers else "no worker of this run"
        self.console.print(
            f"node lost: {node.name} left the cluster ({node.reason}); it held {workers}: "
            "their jobs in flight end as worker_died",
            markup=False,
            highlight=False,
            soft_wrap=True,
        )

    def end(
        self,
        status: Literal["finished", "interrupted", "failed"],
        reason: str | None = None,
        budget_stop: str | None = None,
    ) -> None:
        """Write the session's ``sweep_end``, with what this watcher heard."""
        self._write(
            SweepEnd(
                session=self.session, status=status, reason=reason, sent=self.sent, outcomes=self.outcomes,
                retried=self.retried, cost_usd=self.cost_usd, budget_stop=budget_stop,
                seconds=time.monotonic() - self.began,
            )
        )  # fmt: skip
