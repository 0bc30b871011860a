"""The spans both sides open, and the W3C ``traceparent`` that joins a worker's spans to the driver's trace.

Every span is opened through the API's tracer: a no-op until ``configure_tracing`` (or an application) installs a
provider. Attributes that cost something to compute are set only on a span that records (``recording``).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from opentelemetry import context as otel_context
from opentelemetry import trace
from opentelemetry.trace import Span, Status, StatusCode
from opentelemetry.trace.propagation.tracecontext import TraceContextTextMapPropagator

TRACER_NAME = "scratchworld"
_PROPAGATOR = TraceContextTextMapPropagator()


def tracer() -> trace.Tracer:
    return trace.get_tracer(TRACER_NAME)


def recording() -> bool:
    """Whether the current span records (false without tracing: no attribute is worth computing)."""
    return trace.get_current_span().is_recording()


def traceparent_of(span: Span) -> str | None:
    """``span``'s W3C ``traceparent`` (None for a span that does not record: nothing to join)."""
    if not span.is_recording():
        return None
    carrier: dict[str, str] = {}
    _PROPAGATOR.inject(carrier, context=trace.set_span_in_context(span))
    return carrier.get("traceparent")


def parent_context(traceparent: str | None) -> otel_context.Context | None:
    """The context a ``traceparent`` names, for a child span of the driver's (None: a new trace)."""
    return _PROPAGATOR.extract({"traceparent": traceparent}) if traceparent else None


@contextmanager
def span(name: str, parent: otel_context.Context | None = None, **attributes: Any) -> Iterator[Span]:
    """A span around the block, child of the current one (or of ``parent``); an exception escaping the block is
    recorded on it. Attributes of None are left out."""
    with tracer().start_as_current_span(
        name, context=parent, attributes={k: v for k, v in attributes.items() if v is not None}
    ) as opened:
        yield opened


def set_attributes(opened: Span, **attributes: Any) -> None:
    """Set the attributes that are not None (on a span that records)."""
    if opened.is_recording():
        opened.set_attributes({k: v for k, v in attributes.items() if v is not None})


def mark_error(opened: Span, description: str) -> None:
    """The span's operation failed (an error outcome, not an exception)."""
    if opened.is_recording():
        opened.set_status(Status(StatusCode.ERROR, description[:300]))
