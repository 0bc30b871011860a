"""OpenTelemetry spans of a sweep: job (driver), episode, step, model call, action and evaluation (workers), with
task, mode, model, tokens and outcome as attributes. Off by default (``configure_tracing``: only the standard
``OTEL_*`` variables turn it on); a worker's spans join the driver's trace through the ``traceparent`` its job
carries (``JobHeader.trace_parent``)."""

from workers.tracing._setup import (
    TracingConfigError,
    configure_tracing,
    flush_spans,
    tracing_active,
    tracing_requested,
)
from workers.tracing._spans import (
    mark_error,
    parent_context,
    recording,
    set_attributes,
    span,
    traceparent_of,
    tracer,
)

__all__ = [
    "TracingConfigError",
    "configure_tracing",
    "flush_spans",
    "mark_error",
    "parent_context",
    "recording",
    "set_attributes",
    "span",
    "traceparent_of",
    "tracer",
    "tracing_active",
    "tracing_requested",
]
