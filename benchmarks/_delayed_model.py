"""The density benchmark's model: the tests' OpenAI-compatible server answering every request a set delay after it
arrived, in a process of its own.

A real model is another machine. Served from the benchmark's own process, the server's 64 reply threads share
one GIL with the scheduler and the sampler that reads every process twice a second, so a late reply would count
as the harness's overhead. Here the process does nothing but serve, and the delay is checked from its side: each
reply's lateness (written, less arrival, less the delay) comes back with the arrivals.
"""

from __future__ import annotations

import multiprocessing
import time
from dataclasses import dataclass
from multiprocessing.connection import Connection
from typing import Any

from tests.support.openai_server import Behaviour, OpenAIServer

REPLIES = {
    "composite": "Analysis: a harmless edit.\n```json\n"
    '{"api": "add_block", "args": {"blockType": "event_whenflagclicked"}}\n```',
    "primitive": 'Analysis: a block into the code area.\n```json\n{"api": "drag_and_drop", "args": '
    '{"start_x": 80, "start_y": 170, "end_x": 520, "end_y": 330, "duration": 0.5}}\n```',
}
"""What the model answers, per mode: a valid action that changes the project a little."""


@dataclass(frozen=True)
class Served:
    """What the server saw of the requests so far, in Unix time."""

    waiting: list[tuple[float, float]]
    """(arrival, answer due) of every request: the episode waits on the model in between."""

    lateness: list[float]
    """Per reply written so far: seconds past its due time (the server's own lag)."""


class _Responder:
    """Answers every request ``delay`` seconds after it arrived (the server records when each arrived)."""

    def __init__(self, delay: float) -> None:
        self.delay = delay
        self.reply = REPLIES["composite"]

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        return Behaviour("hang", text=self.reply, seconds=self.delay, prompt_tokens=2000, completion_tokens=40)


def _serve(conn: Connection, delay: float) -> None:
    responder = _Responder(delay)
    unix = time.time() - time.monotonic()  # the server's records are on the monotonic clock, the samples on Unix time
    with OpenAIServer(responder=responder) as server:
        conn.send(server.url)
        while True:
            command, argument = conn.recv()
            if command == "reply":
                responder.reply = argument
                conn.send(None)
            elif command == "served":
                requests = server.requests
                waiting = [(unix + request.time, unix + request.time + delay) for request in requests]
                lateness = [
                    request.replied - request.time - delay for request in requests if request.replied is not None
                ]
                conn.send(Served(waiting, lateness))
            else:
                conn.send(None)
                return


class DelayedModel:
    """The server in a child process (``spawn``: nothing of this process's Ray or threads is inherited)."""

    def __init__(self, delay: float) -> None:
        context = multiprocessing.get_context("spawn")
        self._conn, child = context.Pipe()
        self._process = context.Process(target=_serve, args=(child, delay), name="density-model", daemon=True)
        self.url = ""

    @property
    def pid(self) -> int | None:
        return self._process.pid

    def __enter__(self) -> DelayedModel:
        self._process.start()
        self.url = self._conn.recv()
        return self

    def __exit__(self, *exc: object) -> None:
        self._ask("stop")
        self._process.join(timeout=30)

    def set_reply(self, mode: str) -> None:
        """Every request from now on gets ``mode``'s reply."""
        self._ask("reply", REPLIES[mode])

    def served(self) -> Served:
        return self._ask("served")

    def _ask(self, command: str, argument: object = None) -> Any:
        self._conn.send((command, argument))
        return self._conn.recv()
