"""``events.jsonl``: what a run did, as it happened, one JSON event per line, for tools that follow a run (a log
shipper, a dashboard, ``tail -f | jq``) without reading its tables.

Every ``run`` session appends: ``sweep_start``, then per attempt ``job_start`` and one of ``job_finish`` (a verdict),
``job_retry`` (an error that is sent again) or ``job_error`` (an error after its last retry), then ``sweep_end``
(also when the run stops on an exception or Ctrl-C); ``node_lost`` when a node leaves the cluster meanwhile
(Ray declared it dead: a crash, a partition). A job's events follow the commit of its rows, so an event
never names a result the tables do not hold. Each line is one of the models below (``RunEvent``), told apart by
``event``.
"""

from __future__ import annotations

from datetime import UTC, datetime
from pathlib import Path
from typing import Annotated, Literal

from pydantic import BaseModel, Field, TypeAdapter

EVENTS_NAME = "events.jsonl"


def _now() -> datetime:
    return datetime.now(tz=UTC)


class _Event(BaseModel):
    time: datetime = Field(default_factory=_now)
    session: int
    """The session (``run`` invocation) of the run directory, from 1, as the manifest lists them."""


class SweepStart(_Event):
    event: Literal["sweep_start"] = "sweep_start"
    run_name: str
    planned: int
    already_decided: int
    to_run: int
    host: str
    pid: int
    tags: dict[str, str]


class _JobEvent(_Event):
    job_id: str
    task_id: str
    model: str
    agent: str
    mode: str
    seed: int
    attempt: int


class JobStart(_JobEvent):
    event: Literal["job_start"] = "job_start"
    worker: int
    """The worker it was sent to (sent again, as the same attempt, when a worker declined it or restarted)."""


class JobFinish(_JobEvent):
    event: Literal["job_finish"] = "job_finish"
    outcome: Literal["passed", "failed"]
    tests_passed: int
    tests_total: int
    steps: int
    input_tokens: int
    output_tokens: int
    cost_usd: float
    seconds: float
    """The attempt's wall-clock time, setup to verdict."""


class JobRetry(_JobEvent):
    event: Literal["job_retry"] = "job_retry"
    error_class: str | None
    message: str | None
    cost_usd: float


class JobError(_JobEvent):
    event: Literal["job_error"] = "job_error"
    error_class: str | None
    message: str | None
    cost_usd: float


class NodeLost(_Event):
    event: Literal["node_lost"] = "node_lost"
    node_id: str
    address: str
    hostname: str
    reason: str
    """Ray's words for why it dropped the node (e.g. its health checks failed)."""

    workers: list[int]
    """The run's workers that were on it; their jobs in flight are retried on other workers."""


class SweepEnd(_Event):
    event: Literal["sweep_end"] = "sweep_end"
    status: Literal["finished", "interrupted", "failed"]
    """``interrupted``: Ctrl-C or a signal; ``failed``: an exception stopped the driver (its message)."""

    reason: str | None = None
    sent: int
    outcomes: dict[str, int]
    retried: int
    cost_usd: float
    budget_stop: str | None
    seconds: float


RunEvent = Annotated[
    SweepStart | JobStart | JobFinish | JobRetry | JobError | NodeLost | SweepEnd, Field(discriminator="event")
]
EVENT_ADAPTER: TypeAdapter[RunEvent] = TypeAdapter(RunEvent)
"""Reads one line of ``events.jsonl`` (``EVENT_ADAPTER.validate_json(line)``)."""


class EventLog:
    """Appends events to a run directory's ``events.jsonl``, each line written whole and flushed."""

    def __init__(self, run_dir: Path) -> None:
        self.path = run_dir / EVENTS_NAME
        self._file = self.path.open("a", encoding="utf-8")

    def write(self, event: SweepStart | JobStart | JobFinish | JobRetry | JobError | NodeLost | SweepEnd) -> None:
        self._file.write(event.model_dump_json() + "\n")
        self._file.flush()

    def close(self) -> None:
        self._file.close()


def read_events(run_dir: Path) -> list[RunEvent]:
    """Every event of ``run_dir``, in order (none when it has no ``events.jsonl``)."""
    path = run_dir / EVENTS_NAME
    if not path.exists():
        return []
    return [EVENT_ADAPTER.validate_json(line) for line in path.read_text(encoding="utf-8").splitlines() if line]
