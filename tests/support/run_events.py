"""Run events as a sweep's driver writes them (``events.jsonl``), made by hand for the consumers of that stream."""

from __future__ import annotations

from typing import Any

from scratchworld_dist.results import JobFinish


def job_fields(job_id: str, attempt: int = 1) -> dict[str, Any]:
    """The fields every job event has, for job ``job_id`` (its task named the same)."""
    return {"session": 1, "job_id": job_id, "task_id": job_id, "model": "m", "agent": "a", "mode": "composite",
            "seed": 0, "attempt": attempt}  # fmt: skip


def finish(job_id: str, outcome: str, passed: int, total: int, cost: float = 0.0, attempt: int = 1) -> JobFinish:
    """A verdict of ``passed`` of ``total`` tests."""
    return JobFinish(
        **job_fields(job_id, attempt), outcome=outcome, tests_passed=passed, tests_total=total, steps=1,
        input_tokens=0, output_tokens=0, cost_usd=cost, seconds=1.0,
    )  # fmt: skip
