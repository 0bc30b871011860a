"""The driver's spans of a sweep: one ``sweep`` span per session, and one ``job`` span per attempt, opened when the
attempt is first sent (its ``traceparent`` travels in the job, so the worker's spans join it) and ended when its
result is committed (from the run's events, as the trackers hear them). Only while tracing
(``workers.tracing.configure_tracing``): otherwise the scheduler sends the jobs as planned, untouched."""

from __future__ import annotations

from collections.abc import Callable

from opentelemetry import trace
from opentelemetry.trace import Span

from scratchworld_dist.results import JobError, JobFinish, JobRetry, RunEvent
from scratchworld_dist.sweep import JobSpec
from workers.contract import WorkerJob
from workers.tracing import mark_error, set_attributes, traceparent_of, tracer

Sends = Callable[[JobSpec, int, float], WorkerJob]


class JobSpans:
    """Wraps the scheduler's ``sends`` (each attempt's job gains its span's ``traceparent``) and hears the run's
    events (each attempt's span ends with its outcome, tokens and cost)."""

    def __init__(self, sends: Sends, run_name: str, session: int) -> None:
        self._sends = sends
        self.sweep = tracer().start_span("sweep", attributes={"run": run_name, "session": session})
        self._parent = trace.set_span_in_context(self.sweep)
        self._open: dict[tuple[str, int], Span] = {}

    def sends(self, job: JobSpec, attempt: int, timeout_s: float) -> WorkerJob:
        """The worker's job for ``attempt``, carrying its span's ``traceparent`` (the same span when it is sent
        again, to another worker, as the same attempt)."""
        key = (job.job_id, attempt)
        opened = self._open.get(key)
        if opened is None:
            attributes = {
                "job_id": job.job_id, "task": job.task_id, "category": job.category, "mode": job.mode,
                "model": job.model_name, "agent": job.agent_label, "seed": job.seed, "attempt": attempt,
            }  # fmt: skip
            opened = self._open[key] = tracer().start_span("job", context=self._parent, attributes=attributes)
        spec = self._sends(job, attempt, timeout_s)
        if "trace_parent" not in type(spec).model_fields:  # a plugin's spec need not extend JobHeader
            return spec
        return spec.model_copy(update={"trace_parent": traceparent_of(opened)})

    def hear(self, event: RunEvent) -> None:
        if not isinstance(event, JobFinish | JobRetry | JobError):
            return
        opened = self._open.pop((event.job_id, event.attempt), None)
        if opened is None:
            return
        set_attributes(opened, outcome=getattr(event, "outcome", "error"), cost_usd=event.cost_usd)
        if isinstance(event, JobFinish):
            set_attributes(
                opened, input_tokens=event.input_tokens, output_tokens=event.output_tokens,
                tests_passed=event.tests_passed, tests_total=event.tests_total, steps=event.steps,
            )  # fmt: skip
        else:
            set_attributes(opened, error_class=event.error_class, retried=isinstance(event, JobRetry))
            mark_error(opened, event.error_class or "error")
        opened.end()

    def end(self, status: str) -> None:
        """End the session's spans (attempts still open: the sweep stopped before their results)."""
        for opened in self._open.values():
            set_attributes(opened, outcome="unfinished")
            opened.end()
        self._open.clear()
        set_attributes(self.sweep, status=status)
        self.sweep.end()
