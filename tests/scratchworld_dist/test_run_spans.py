"""A traced sweep's driver: a ``sweep`` span per session and a ``job`` span per attempt with its outcome, while the
jobs keep their identity (an untraced session of the same run finds them decided). Synthetic episodes on a real
local Ray; the driver's spans in the SDK's in-memory exporter."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml
from opentelemetry import trace

from tests.conftest import REPO
from tests.support.sweep_driver import run_here
from tests.support.traced_worker import SpanRecord, spans_here

pytestmark = pytest.mark.ray

TASKS = ["sum_two_numbers", "quiz_score"]


@pytest.fixture
def driver_spans(monkeypatch: pytest.MonkeyPatch) -> Iterator[Any]:
    with spans_here(monkeypatch) as exporter:
        yield exporter


def test_a_traced_sweep_has_a_span_per_attempt_and_the_same_jobs(
    tmp_path: Path, shared_ray: int, driver_spans: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    config = {
        "name": "traced", "suite": str(REPO / "tasks"), "agent": "oracle", "output": str(tmp_path / "run"),
        "tasks": {"ids": TASKS}, "episodes": {"synthetic": {"fail_tasks": ["quiz_score"]}},
    }  # fmt: skip
    path = tmp_path / "sweep.yaml"
    path.write_text(yaml.safe_dump(config))
    code, out = run_here(path, "--progress", "none")
    assert code == 0, out
    spans = [SpanRecord.of(span) for span in driver_spans.get_finished_spans()]
    [sweep] = [span for span in spans if span.name == "sweep"]
    jobs = {span.attributes["task"]: span for span in spans if span.name == "job"}
    assert sweep.attributes == {"run": "traced", "session": 1, "status": "finished"}
    assert {task: span.attributes["outcome"] for task, span in jobs.items()} == {
        "sum_two_numbers": "passed", "quiz_score": "failed",
    }  # fmt: skip
    assert all(span.parent_id == sweep.span_id and span.trace_id == sweep.trace_id for span in jobs.values())
    assert all(span.attributes["mode"] == "composite" and span.attributes["attempt"] == 1 for span in jobs.values())

    monkeypatch.setattr(trace, "_TRACER_PROVIDER", None)  # untraced from here: the same jobs, already decided
    code, out = run_here(path, "--progress", "none")
    assert code == 0, out
    assert "2 already decided, 0 to run" in out
