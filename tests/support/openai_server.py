"""A real OpenAI-compatible chat-completions server for tests, driven by a script of behaviours.

Each request takes the next behaviour from the script (the ``default`` once it runs out): a reply,
an HTTP error, a hang, a dropped connection or a malformed body. Every request is recorded with
its headers, JSON body and arrival time so tests can assert counts, headers, forwarded parameters
and pacing. The server is a stdlib ``ThreadingHTTPServer`` on 127.0.0.1 (or another address of a network
namespace a test made) with an ephemeral port.
"""

from __future__ import annotations

import contextlib
import json
import socket
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any, Literal

CHAT_PATHS = ("/v1/chat/completions", "/chat/completions")

CONTEXT_LENGTH_MESSAGE = (
    "This model's maximum context length is 8192 tokens. However, your messages resulted in 9000 tokens. "
    "Please reduce the length of the messages."
)


@dataclass(frozen=True)
class Behaviour:
    """What the server does with one request."""

    kind: Literal["reply", "status", "hang", "drop", "malformed"]
    text: str = "ok"
    prompt_tokens: int = 10
    completion_tokens: int = 5
    model: str | None = None
    code: int = 200
    retry_after: str | None = None
    body: Any = None
    seconds: float = 0.0
    reasoning: str | None = None
    """Sent as the message's ``reasoning_content``, as reasoning models' providers do."""


def reply(text: str = "ok", prompt_tokens: int = 10, completion_tokens: int = 5, model: str | None = None) -> Behaviour:
    """A 200 with a valid chat completion (``model`` defaults to the one requested)."""
    return Behaviour("reply", text=text, prompt_tokens=prompt_tokens, completion_tokens=completion_tokens, model=model)


def status(code: int, retry_after: float | str | None = None, body: Any = None) -> Behaviour:
    """An HTTP error with an OpenAI-style error body (or ``body`` as given: a dict or a string)."""
    header = None if retry_after is None else str(retry_after)
    return Behaviour("status", code=code, retry_after=header, body=body)


def context_length_error() -> Behaviour:
    """The 400 OpenAI answers when the prompt does not fit the model's context window."""
    error = {"message": CONTEXT_LENGTH_MESSAGE, "type": "invalid_request_error", "code": "context_length_exceeded"}
    return status(400, body={"error": error})


def hang(seconds: float) -> Behaviour:
    """Say nothing for ``seconds`` (cut short when the server closes), then reply."""
    return Behaviour("hang", seconds=seconds)


def drop() -> Behaviour:
    """Read the request, then close the socket without answering."""
    return Behaviour("drop")


def malformed() -> Behaviour:
    """A 200 whose body is not JSON."""
    return Behaviour("malformed")


@dataclass
class RecordedRequest:
    """One request as the server saw it."""

    path: str
    headers: dict[str, str]
    """Header names lower-cased."""

    body: Any
    """The parsed JSON body (None when it was not JSON)."""

    time: float
    """``time.monotonic()`` at arrival (same clock as the test process)."""

    behaviour: Behaviour = field(repr=False, default_factory=lambda: reply())

    replied: float | None = None
    """``time.monotonic()`` once the request was answered (or dropped); None until then."""


_ERROR_TYPES = {
    400: "invalid_request_error",
    401: "invalid_api_key",
    403: "permission_denied",
    404: "not_found_error",
    429: "rate_limit_exceeded",
}


class OpenAIServer:
    """The server; use it as a context manager (``with OpenAIServer(script) as server:``)."""

    def __init__(
        self,
        script: Iterable[Behaviour] = (),
        default: Behaviour | None = None,
        responder: Callable[[dict[str, Any]], Behaviour] | None = None,
        host: str = "127.0.0.1",
    ) -> None:
        """``responder``, when given, answers each request (by its JSON body) once the script has run out;
        ``host``: the address to listen on (loopback, but for hosts a test made: ``tests/support/netns_hosts.py``)."""
        self.host = host
        self._script: deque[Behaviour] = deque(script)
        self.default = default or reply()
        self.responder = responder
        self._lock = threading.Lock()
        self._requests: list[RecordedRequest] = []
        self._closing = threading.Event()
        self._open = threading.Event()
        self._open.set()
        self._httpd: _QuietServer | None = None
        self._thread: threading.Thread | None = None

    # -- lifecycle -------------------------------------------------------------------------------------------

    def start(self) -> OpenAIServer:
        handler = type("Handler", (_Handler,), {"owner": self})
        self._httpd = _QuietServer((self.host, 0), handler)
        self._thread = threading.Thread(
            target=self._httpd.serve_forever, kwargs={"poll_interval": 0.05}, name="openai-test-server", daemon=True
        )
        self._thread.start()
        return self

    def close(self) -> None:
        self._closing.set()
        if self._httpd is not None:
            self._httpd.shutdown()
            self._httpd.server_close()
            self._httpd = None
        if self._thread is not None:
            self._thread.join(timeout=5)
            self._thread = None

    def __enter__(self) -> OpenAIServer:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.close()

    # -- script and records ----------------------------------------------------------------------------------

    @property
    def url(self) -> str:
        """The ``api_base`` to give a client (ends in ``/v1``)."""
        assert self._httpd is not None, "server not started"
        return f"http://{self.host}:{self._httpd.server_address[1]}/v1"

    def hold(self) -> None:
        """Keep every reply (scripted or not) waiting until ``release``; requests are still recorded."""
        self._open.clear()

    def release(self) -> None:
        self._open.set()

    def reset(self, responder: Callable[[dict[str, Any]], Behaviour] | None = None) -> OpenAIServer:
        """Forget the script and the requests so far and answer with ``responder``: one server serves a
        module's tests (its address can then be in the environment of a Ray started once)."""
        with self._lock:
            self._script.clear()
            self._requests.clear()
            self.responder = responder
        self.release()
        return self

    def push(self, *behaviours: Behaviour) -> None:
        with self._lock:
            self._script.extend(behaviours)

    @property
    def requests(self) -> list[RecordedRequest]:
        with self._lock:
            return list(self._requests)

    @property
    def count(self) -> int:
        with self._lock:
            return len(self._requests)

    def _next(self, request: RecordedRequest) -> Behaviour:
        with self._lock:
            if self._script:
                behaviour = self._script.popleft()
            elif self.responder is not None:
                behaviour = self.responder(request.body if isinstance(request.body, dict) else {})
            else:
                behaviour = self.default
            request.behaviour = behaviour
            self._requests.append(request)
            return behaviour


class _QuietServer(ThreadingHTTPServer):
    daemon_threads = True

    def handle_error(self, request: Any, client_address: Any) -> None:
        """A client that timed out or hung up mid-answer is expected here; say nothing."""


class _Handler(BaseHTTPRequestHandler):
    owner: OpenAIServer
    protocol_version = "HTTP/1.1"

    def log_message(self, format: str, *args: Any) -> None:
        """Silence the per-request stderr lines."""

    def do_POST(self) -> None:
        length = int(self.headers.get("content-length") or 0)
        raw = self.rfile.read(length) if length else b""
        try:
            body = json.loads(raw)
        except ValueError:
            body = None
        if self.path.split("?")[0] not in CHAT_PATHS:
            self._send_json(404, {"error": {"message": f"no route {self.path}", "type": "not_found_error"}})
            return
        headers = {name.lower(): value for name, value in self.headers.items()}
        request = RecordedRequest(path=self.path, headers=headers, body=body, time=time.monotonic())
        behaviour = self.owner._next(request)
        with contextlib.suppress(OSError):
            self._perform(behaviour, body if isinstance(body, dict) else {})
            request.replied = time.monotonic()

    def _perform(self, behaviour: Behaviour, body: dict[str, Any]) -> None:
        if behaviour.kind == "drop":
            self.close_connection = True
            with contextlib.suppress(OSError):
                self.connection.shutdown(socket.SHUT_RDWR)
            self.connection.close()
            return
        if behaviour.kind == "malformed":
            self._send_raw(200, b"<html>this is not json", "application/json")
            return
        if behaviour.kind == "status":
            self._send_error(behaviour)
            return
        if behaviour.kind == "hang":
            self.owner._closing.wait(behaviour.seconds)
        while not self.owner._open.wait(0.05) and not self.owner._closing.is_set():
            continue  # held: the reply waits for ``release`` (or the server's close)
        self._send_json(200, _completion(behaviour, body))

    def _send_error(self, behaviour: Behaviour) -> None:
        payload = behaviour.body
        if payload is None:
            kind = _ERROR_TYPES.get(behaviour.code, "server_error")
            payload = {"error": {"message": f"scripted HTTP {behaviour.code}", "type": kind, "code": None}}
        extra = {"retry-after": behaviour.retry_after} if behaviour.retry_after is not None else {}
        if isinstance(payload, str):
            self._send_raw(behaviour.code, payload.encode(), "text/plain", extra)
        else:
            self._send_json(behaviour.code, payload, extra)

    def _send_json(self, code: int, payload: Any, extra: dict[str, str] | None = None) -> None:
        self._send_raw(code, json.dumps(payload).encode(), "application/json", extra)

    def _send_raw(self, code: int, data: bytes, content_type: str, extra: dict[str, str] | None = None) -> None:
        self.send_response(code)
        self.send_header("content-type", content_type)
        self.send_header("content-length", str(len(data)))
        for name, value in (extra or {}).items():
            self.send_header(name, value)
        self.end_headers()
        self.wfile.write(data)
        self.wfile.flush()


def _completion(behaviour: Behaviour, body: dict[str, Any]) -> dict[str, Any]:
    model = behaviour.model or str(body.get("model") or "test-model")
    usage = {
        "prompt_tokens": behaviour.prompt_tokens,
        "completion_tokens": behaviour.completion_tokens,
        "total_tokens": behaviour.prompt_tokens + behaviour.completion_tokens,
    }
    return {
        "id": f"chatcmpl-{time.monotonic_ns()}",
        "object": "chat.completion",
        "created": int(time.time()),
        "model": model,
        "choices": [
            {
                "index": 0,
                "message": {"role": "assistant", "content": behaviour.text}
                | ({"reasoning_content": behaviour.reasoning} if behaviour.reasoning else {}),
                "finish_reason": "stop",
            }
        ],
        "usage": usage,
    }
