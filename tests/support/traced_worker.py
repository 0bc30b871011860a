"""Spans read back from where they were made: the SDK's in-memory exporter, in this process or in a Ray worker."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import pytest
from pydantic import BaseModel

from workers.actor import JobWorker


class SpanRecord(BaseModel):
    """A finished span as a test reads it (and as it crosses back from a Ray worker)."""

    name: str
    trace_id: str
    span_id: str
    parent_id: str | None
    attributes: dict[str, Any]

    @classmethod
    def of(cls, span: Any) -> SpanRecord:
        parent = span.parent
        return cls(
            name=span.name,
            trace_id=f"{span.context.trace_id:032x}",
            span_id=f"{span.context.span_id:016x}",
            parent_id=f"{parent.span_id:016x}" if parent is not None else None,
            attributes=dict(span.attributes or {}),
        )


def memory_provider(batched: bool = False) -> tuple[Any, Any]:
    """An SDK tracer provider whose spans go to an in-memory exporter: (provider, exporter). Each span as it ends,
    or ``batched``: only when the provider is flushed (the batch processor's schedule is far beyond any test)."""
    from opentelemetry.sdk.trace import TracerProvider
    from opentelemetry.sdk.trace.export import BatchSpanProcessor, SimpleSpanProcessor
    from opentelemetry.sdk.trace.export.in_memory_span_exporter import InMemorySpanExporter

    exporter = InMemorySpanExporter()
    provider = TracerProvider()
    if batched:
        provider.add_span_processor(BatchSpanProcessor(exporter, schedule_delay_millis=3_600_000))
    else:
        provider.add_span_processor(SimpleSpanProcessor(exporter))
    return provider, exporter


@contextmanager
def spans_here(monkeypatch: pytest.MonkeyPatch) -> Iterator[Any]:
    """This process's spans kept in memory (the exporter) until the test ends, when the API's global provider is
    restored (the API lets a provider be set once per process: a test sets it as a fixture would, and undoes it)."""
    from opentelemetry import trace

    provider, exporter = memory_provider()
    monkeypatch.setattr(trace, "_TRACER_PROVIDER", provider)
    try:
        yield exporter
    finally:
        provider.shutdown()


class TracedJobWorker(JobWorker):
    """The worker actor with its spans kept in memory (``finished_spans``); construct through ``ray.remote``. Its
    spans are batched as an exporter's are: the test sees those the worker flushed itself."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        from opentelemetry import trace

        provider, self.exporter = memory_provider(batched=True)
        trace.set_tracer_provider(provider)  # this actor's own process
        super().__init__(*args, **kwargs)

    async def finished_spans(self) -> list[SpanRecord]:
        return [SpanRecord.of(span) for span in self.exporter.get_finished_spans()]
