"""Tracing is off unless the standard ``OTEL_*`` variables ask for it: then no SDK module is even imported; an
exporter they name that is not installed is one clear error. Each case runs in a fresh interpreter."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from workers.tracing import tracing_requested

PROBE = (
    "import json, sys\n"
    "from workers.tracing import TracingConfigError, tracing_active, span\n"
    "try:\n"
    "    active = tracing_active()\n"
    "except TracingConfigError as exc:\n"
    "    print('RESULT', json.dumps({'error': str(exc)})); sys.exit()\n"
    "with span('probe', task='t') as s:\n"
    "    recording = s.is_recording()\n"
    "sdk = any(name.startswith('opentelemetry.sdk') for name in sys.modules)\n"
    "print('RESULT', json.dumps({'active': active, 'recording': recording, 'sdk': sdk}))\n"
)


def probe(**variables: str) -> dict[str, object]:
    environ = {k: v for k, v in os.environ.items() if not k.startswith("OTEL_")} | variables
    done = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, timeout=120, env=environ)
    assert done.returncode == 0, done.stderr
    [line] = [line for line in done.stdout.splitlines() if line.startswith("RESULT ")]  # a console exporter prints too
    return json.loads(line.removeprefix("RESULT "))


def test_without_otel_variables_no_sdk_is_imported_and_spans_do_not_record() -> None:
    assert probe() == {"active": False, "recording": False, "sdk": False}
    assert probe(OTEL_TRACES_EXPORTER="none", OTEL_EXPORTER_OTLP_ENDPOINT="http://127.0.0.1:4318") == {
        "active": False, "recording": False, "sdk": False,
    }  # fmt: skip


def test_otel_variables_turn_the_sdk_on() -> None:
    assert probe(OTEL_TRACES_EXPORTER="console") == {"active": True, "recording": True, "sdk": True}
    assert probe(OTEL_EXPORTER_OTLP_ENDPOINT="http://127.0.0.1:9")["recording"] is True  # otlp, the default


def test_an_exporter_that_is_not_installed_is_named() -> None:
    found = probe(OTEL_TRACES_EXPORTER="jaeger_thrift")
    assert str(found["error"]).startswith("OTEL_TRACES_EXPORTER names jaeger_thrift, not installed here (installed: ")


@pytest.mark.parametrize(
    ("variables", "requested"),
    [
        ({}, False),
        ({"OTEL_TRACES_EXPORTER": "otlp"}, True),
        ({"OTEL_TRACES_EXPORTER": "none", "OTEL_EXPORTER_OTLP_ENDPOINT": "http://x"}, False),
        ({"OTEL_EXPORTER_OTLP_TRACES_ENDPOINT": "http://x"}, True),
        ({"OTEL_EXPORTER_OTLP_ENDPOINT": "http://x", "OTEL_SDK_DISABLED": "true"}, False),
        ({"OTEL_SERVICE_NAME": "lab"}, False),
    ],
)
def test_which_variables_ask_for_spans(variables: dict[str, str], requested: bool) -> None:
    assert tracing_requested(variables) is requested
