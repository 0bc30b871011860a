"""An attempt traced end to end: the driver's ``job`` span, its ``traceparent`` carried in the job to a real Ray
worker, whose ``episode``, ``step``, ``model_call``, ``action`` and ``evaluation`` spans join the driver's trace with
task, mode, model, tokens and outcome; the job's identity is untouched."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest
import ray

from scratchworld_dist._run_spans import JobSpans
from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.results import JobFinish
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from tests.support.openai_server import OpenAIServer, reply
from tests.support.traced_worker import SpanRecord, TracedJobWorker, spans_here
from workers.contract import JobResult, ModelSpec

pytestmark = [pytest.mark.ray, pytest.mark.browser]

DONE_REPLY = 'Analysis: finished.\n```json\n{"api": "done", "args": {}}\n```'


@pytest.fixture
def driver_spans(monkeypatch: pytest.MonkeyPatch) -> Iterator[Any]:
    with spans_here(monkeypatch) as exporter:
        yield exporter


def by_name(spans: list[SpanRecord], name: str) -> list[SpanRecord]:
    return [span for span in spans if span.name == name]


def test_worker_spans_join_the_drivers_trace(driver_spans: Any, model_server: OpenAIServer, model_ray: int) -> None:
    model_server.reset(lambda _: reply(DONE_REPLY, prompt_tokens=120, completion_tokens=7))
    content = read_task(load_suite(SUITE_DIR).task("sum_two_numbers"))
    model = ModelSpec(name="m", model="openai/m", api_base_env="SCRATCHWORLD_LLM_BASE_URL",
                      api_key_env="SCRATCHWORLD_LLM_API_KEY")  # fmt: skip
    matrix = EpisodeMatrix(models=[model], modes=["composite"], agent="llm", tasks=[content], seeds=[0], max_steps=3)
    (job,) = plan_jobs(matrix)
    spans = JobSpans(worker_job, "traced", 1)
    sent = spans.sends(job, 1, 120)
    assert sent.trace_parent is not None
    assert sent.model_copy(update={"trace_parent": None}) == worker_job(job, 1, 120)  # the job as planned
    (again,) = plan_jobs(matrix)
    assert again.job_id == job.job_id

    worker = ray.remote(TracedJobWorker).remote(worker_index=0)
    try:
        result: JobResult = ray.get(worker.run.remote(sent, content.payload), timeout=300)
        worker_spans = ray.get(worker.finished_spans.remote())
    finally:
        ray.get(worker.close.remote())
        ray.kill(worker)
    assert result.outcome in ("passed", "failed"), result.error_message
    evaluation = result.evaluation
    assert evaluation is not None
    spans.hear(
        JobFinish(
            session=1, job_id=job.job_id, task_id=job.task_id, model=job.model_name, agent=job.agent_label,
            mode=job.mode, seed=0, attempt=1, outcome=result.outcome, tests_passed=evaluation.passed,
            tests_total=evaluation.total, steps=len(result.steps), input_tokens=result.input_tokens,
            output_tokens=result.output_tokens, cost_usd=result.cost_usd, seconds=result.timings.total_s,
        )
    )  # fmt: skip
    spans.end("finished")
    here = [SpanRecord.of(span) for span in driver_spans.get_finished_spans()]

    [sweep], [job_span] = by_name(here, "sweep"), by_name(here, "job")
    assert job_span.parent_id == sweep.span_id
    assert (
        job_span.attributes | {"outcome": result.outcome, "input_tokens": 120, "output_tokens": 7}
        == job_span.attributes
    )
    assert (job_span.attributes["task"], job_span.attributes["mode"], job_span.attributes["model"]) == (
        "sum_two_numbers", "composite", "m",
    )  # fmt: skip

    [episode] = by_name(worker_spans, "episode")
    assert (episode.trace_id, episode.parent_id) == (sweep.trace_id, job_span.span_id)  # one trace, across Ray
    assert episode.attributes["outcome"] == result.outcome
    assert (episode.attributes["task"], episode.attributes["mode"], episode.attributes["model"]) == (
        "sum_two_numbers", "composite", "m",
    )  # fmt: skip
    assert episode.attributes["input_tokens"] == 120
    [step] = by_name(worker_spans, "step")
    assert step.parent_id == episode.span_id and step.attributes["action"] == "done"
    [call] = by_name(worker_spans, "model_call")
    assert call.parent_id == step.span_id
    assert (call.attributes["model"], call.attributes["input_tokens"], call.attributes["output_tokens"]) == (
        "m",
        120,
        7,
    )
    [action] = by_name(worker_spans, "action")
    assert action.parent_id == step.span_id and action.attributes["action"] == "done"
    [judged] = by_name(worker_spans, "evaluation")
    assert judged.parent_id == episode.span_id
    assert (judged.attributes["outcome"], judged.attributes["tests_total"]) == (result.outcome, evaluation.total)
    assert {span.trace_id for span in worker_spans} == {sweep.trace_id}
