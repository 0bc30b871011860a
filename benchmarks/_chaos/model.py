"""The model the chaos sweep talks to: a task's golden trajectory as replies, and a seeded share of faults.

A responder of the test OpenAI server (``tests/support/openai_server.py``). Requests are taken in blocks
of ``BLOCK``; in each, a seeded shuffle picks ``fault_rate`` of them to get a 429 (with
``Retry-After``), a 500, or no answer until the client's request timeout has passed, so the
share of faulty calls is the rate itself rather than a draw around it. The others are answered
like a model that knows the task: one action of the golden trajectory per turn (the turn is the
number of replies in the conversation, so a retried request gets the same answer), then
``done``. Tasks listed as ``lazy`` get ``done`` at once: their real episodes end failed.
"""

from __future__ import annotations

import json
import random
from collections import Counter
from typing import Any

from tests.support.openai_server import Behaviour, hang, reply, status

FAULTS = ("429", "500", "timeout")
BLOCK = 20
"""Requests per shuffled block of the fault schedule."""


def answer(action: dict[str, Any]) -> str:
    """A reply in the format the llm agent asks for."""
    return f"Analysis: next step.\n```json\n{json.dumps(action)}\n```"


class ChaoticModel:
    """Answers by the conversation alone; which requests fail, and how, follows the seed."""

    def __init__(
        self,
        seed: int,
        fault_rate: float,
        trajectories: dict[str, list[dict[str, Any]]],
        lazy: set[str],
        request_timeout_s: float,
    ) -> None:
        """``trajectories`` maps a task's instruction to its actions; ``lazy`` holds instructions."""
        self._rng = random.Random(seed)
        self.fault_rate = fault_rate
        self.trajectories = trajectories
        self.lazy = lazy
        self.hang_s = request_timeout_s + 1.0
        self.counts: Counter[str] = Counter()
        """Requests by what they got: ``reply`` or one of ``FAULTS`` (the server calls this under its lock)."""

        self._block: list[str] = []

    def _next_fault(self) -> str | None:
        if not self._block:
            faults = round(self.fault_rate * BLOCK)
            self._block = [self._rng.choice(FAULTS) for _ in range(faults)] + ["reply"] * (BLOCK - faults)
            self._rng.shuffle(self._block)
        fault = self._block.pop()
        return None if fault == "reply" else fault

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        fault = self._next_fault()
        if fault is not None:
            self.counts[fault] += 1
            if fault == "429":
                return status(429, retry_after="0.5")
            if fault == "500":
                return status(500)
            return hang(self.hang_s)
        self.counts["reply"] += 1
        messages = body.get("messages") or [{}]
        system = str(messages[0].get("content", ""))
        turn = sum(1 for m in messages if m.get("role") == "assistant")
        if any(instruction in system for instruction in self.lazy):
            return reply(answer({"api": "done", "args": {}}))
        trajectory = next((t for i, t in self.trajectories.items() if i in system), [])
        action = trajectory[turn] if turn < len(trajectory) else {"api": "done", "args": {}}
        return reply(answer(action))

    @property
    def faulty(self) -> int:
        return sum(self.counts[f] for f in FAULTS)
