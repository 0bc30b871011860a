"""The visual perception QA benchmark's own contract: an item, the job a worker is given, and what one answer to
it was.

A perception job (``PerceptionSpec``) is one model call about one static screenshot: no editor, no action. It
returns an ordinary ``JobResult`` (one step, the answer; one test, "the answer is right" under the normalized
scoring) carrying a ``PerceptionAttempt`` with the reply read both ways: ``strict`` as upstream scores it,
``normalized`` as we do. The answer's format and value kind are the agent API's words (``workers.agent_api``).
"""

from __future__ import annotations

from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from workers.agent_api import AnswerFormat, ValueKind
from workers.contract import AgentJob, JobDetail

QuestionKind = Literal["connection", "existence", "field"]
"""``connection``: is block A attached to block B, or in that slot; ``existence``: is a block of this kind
visible; ``field``: what a block's field shows (or whether it shows a given value)."""

PERCEPTION_KINDS: tuple[QuestionKind, ...] = ("connection", "existence", "field")

YES, NO = "YES", "NO"

AnswerParse = Literal["ok", "no_answer", "unparsed"]
"""How the normalized scoring read a reply: an answer found, an empty reply, or no answer of the asked
form in it (a YES/NO question answered with neither)."""


def answer_problem(answer_format: AnswerFormat, value_kind: ValueKind | None, answer: str) -> str | None:
    """Why an answer does not fit its form (a yes/no answer other than YES or NO, a value kind on the wrong
    item), or None: the one rule for items as suites hold them and as workers get them."""
    if answer_format == "yes_no" and answer not in (YES, NO):
        return f"a yes_no item's answer is YES or NO, not {answer!r}"
    if (answer_format == "value") != (value_kind is not None):
        return "value_kind (number, text or dropdown) is given exactly for value items"
    return None


class PerceptionPayload(BaseModel):
    """One item's content, shipped once per item to the object store and shared by its jobs.

    ``answer`` reaches the worker for scoring and for the scripted agents, never a model's prompt.
    """

    model_config = ConfigDict(frozen=True)

    item_id: str
    kind: QuestionKind
    tag: str
    """Finer class of the item (upstream's tags, e.g. ``connection_no_hard``, or ours)."""

    question: str = Field(min_length=1)
    answer_format: AnswerFormat
    value_kind: ValueKind | None = None
    answer: str = Field(min_length=1)
    screenshot_png: bytes = Field(repr=False)

    @model_validator(mode="after")
    def _answer_fits_format(self) -> PerceptionPayload:
        problem = answer_problem(self.answer_format, self.value_kind, self.answer)
        if problem is not None:
            raise ValueError(problem)
        return self


class PerceptionSpec(AgentJob):
    """One perception job as a worker sees it: who answers which item (``task_id`` is the item's id)."""


class PerceptionScore(BaseModel):
    """One reply judged against an item's answer, both ways."""

    model_config = ConfigDict(frozen=True)

    strict: bool
    """Upstream's rule: the stripped reply equals the answer (YES/NO case-insensitively, values exactly)."""

    normalized: bool
    """Ours: the final answer read out of the reply, quotes and punctuation trimmed, numbers as numbers,
    dropdown options case-insensitively."""

    extracted: str | None
    """The answer the normalized reading found (None when it found none)."""

    parse: AnswerParse


class PerceptionAttempt(JobDetail):
    """What one perception job answered and how it scored."""

    kind: Literal["perception"] = "perception"

    reply: str
    """The answer as given: the model's raw reply, or a scripted agent's answer."""

    expected: str
    score: PerceptionScore
    screenshot_sha256: str
    """The item's screenshot, stored once per run under ``images/``."""
