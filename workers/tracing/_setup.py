"""Whether this process records spans, decided once from the standard ``OTEL_*`` variables (off by default).

Without them nothing of the OpenTelemetry SDK is imported: the API's tracer stays its no-op proxy, whose spans cost
a function call. With them the SDK's tracer provider is installed, exporting through what ``OTEL_TRACES_EXPORTER``
names (default ``otlp``: OTLP over HTTP, or gRPC as ``OTEL_EXPORTER_OTLP_PROTOCOL`` says; ``console``; any exporter
installed under the SDK's ``opentelemetry_traces_exporter`` entry points), each behind a batch processor. The
exporters read their own variables (``OTEL_EXPORTER_OTLP_ENDPOINT``, headers...), the resource ``OTEL_SERVICE_NAME``
and ``OTEL_RESOURCE_ATTRIBUTES``. Ray workers read the variables of their node's environment (a local Ray's workers
inherit the driver's).
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from importlib.metadata import entry_points

REQUESTING = ("OTEL_TRACES_EXPORTER", "OTEL_EXPORTER_OTLP_ENDPOINT", "OTEL_EXPORTER_OTLP_TRACES_ENDPOINT")
"""Any of these set (and the SDK not disabled) turns tracing on."""

DEFAULT_SERVICE = "scratchworld"
EXPORTER_GROUP = "opentelemetry_traces_exporter"

_configured: bool | None = None


class TracingConfigError(ValueError):
    """``OTEL_TRACES_EXPORTER`` names an exporter that is not installed."""


def tracing_requested(environ: Mapping[str, str] = os.environ) -> bool:
    """Whether the environment asks for spans: an exporter named (not ``none``) or an OTLP endpoint given."""
    if environ.get("OTEL_SDK_DISABLED", "").strip().lower() == "true":
        return False
    named = environ.get("OTEL_TRACES_EXPORTER")
    if named is not None:
        return named.strip().lower() not in ("", "none")
    return any(environ.get(variable) for variable in REQUESTING[1:])


def configure_tracing() -> bool:
    """Install the SDK's tracer provider once per process if the environment asks for spans (see the module);
    whether spans are recorded. A provider installed before (a test's, an application's) is kept."""
    global _configured
    if _configured is None:
        _configured = tracing_requested() and _install()
    return _configured


def tracing_active() -> bool:
    """Whether spans are recorded in this process: the environment asked (``configure_tracing``), or an
    application or test installed a tracer provider of its own."""
    from opentelemetry import trace

    return configure_tracing() or not isinstance(trace.get_tracer_provider(), trace.ProxyTracerProvider)


def flush_spans(timeout_s: float = 2.0) -> bool:
    """Export the spans ended so far (a Ray worker is killed without running its exit handlers); whether they
    were exported within ``timeout_s``."""
    from opentelemetry import trace

    flush = getattr(trace.get_tracer_provider(), "force_flush", None)
    return bool(flush(int(timeout_s * 1000))) if flush is not None else True


def _exporter_name(name: str) -> str:
    """``otlp`` as the protocol variables choose it (the specification's default: HTTP with protobuf)."""
    if name != "otlp":
        return name
    protocol = os.environ.get("OTEL_EXPORTER_OTLP_TRACES_PROTOCOL") or os.environ.get("OTEL_EXPORTER_OTLP_PROTOCOL")
    return "otlp_proto_grpc" if (protocol or "").strip() == "grpc" else "otlp_proto_http"


def _install() -> bool:
    from opentelemetry import trace
    from opentelemetry.sdk.resources import Resource
    from opentelemetry.sdk.trace import TracerProvider
    from opentelemetry.sdk.trace.export import BatchSpanProcessor

    if isinstance(trace.get_tracer_provider(), TracerProvider):
        return True  # someone set one up already: spans go where they said
    names = [_exporter_name(n.strip()) for n in os.environ.get("OTEL_TRACES_EXPORTER", "otlp").split(",") if n.strip()]
    installed = {point.name: point for point in entry_points(group=EXPORTER_GROUP)}
    missing = [name for name in names if name not in installed]
    if missing:
        known = ", ".join(sorted(installed)) or "none"
        raise TracingConfigError(
            f"OTEL_TRACES_EXPORTER names {', '.join(missing)}, not installed here (installed: {known}); "
            "pip install 'scratchworld-dist[otlp]' for otlp"
        )
    attributes = {} if os.environ.get("OTEL_SERVICE_NAME") else {"service.name": DEFAULT_SERVICE}
    provider = TracerProvider(resource=Resource.create(attributes))
    for name in names:
        provider.add_span_processor(BatchSpanProcessor(installed[name].load()()))
    trace.set_tracer_provider(provider)
    return True
