"""The exploration plan of a task: the runs of a program, independent of the task's tests, under which a variant
the tests misjudge is compared with the golden. The driver makes it (``scratchworld_dist.kinds.audit``) from the
golden's hat blocks and the task's instruction; the page runs each episode (``scratch-gui/explore/``) in virtual
time, with a seeded ``Math.random``, so an episode of one program is the same run every time.

An answer outside the task's answer domain (``AnswerDomain``: a number where the instruction asks for one, a
word...) is one the instruction rules out: a difference only such answers show is no hole (``in_domain``).
"""

from __future__ import annotations

import re
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue, model_validator

StimulusKind = Literal["green_flag", "key", "click", "stage_click", "backdrop", "broadcast"]

AnswerDomain = Literal["any", "text", "numbers", "integers", "words"]
"""The answers a task's instruction allows to its questions: ``any`` (the empty answer too), ``text`` (anything
but empty), ``numbers``, ``integers`` (whole numbers), ``words`` (text with a letter that is no number)."""

ANSWER_DOMAINS: tuple[AnswerDomain, ...] = ("any", "text", "numbers", "integers", "words")

MAX_EPISODES = 16
MAX_SPAN_MS = 120_000

_NUMBER = re.compile(r"^\s*[-+]?(\d+\.?\d*|\.\d+)(e[-+]?\d+)?\s*$", re.IGNORECASE)
_INTEGER = re.compile(r"^\s*[-+]?\d+\s*$")


def in_domain(answer: str, domain: AnswerDomain) -> bool:
    """Whether the instruction allows ``answer`` (numbers as Scratch reads them: decimal, sign, exponent)."""
    if domain == "any":
        return True
    if domain == "text":
        return answer.strip() != ""
    if domain == "numbers":
        return _NUMBER.match(answer) is not None
    if domain == "integers":
        return _INTEGER.match(answer) is not None
    return any(ch.isalpha() for ch in answer) and _NUMBER.match(answer) is None


class Stimulus(BaseModel):
    """One thing done to the program at one moment of an episode."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    at_ms: int = Field(ge=0)
    kind: StimulusKind
    name: str = ""
    """The key (Scratch's name: ``space``, ``left arrow``, ``a``), sprite, backdrop or message."""

    hold_ms: int = Field(default=0, ge=0)
    """How long a key is held."""

    def describe(self) -> str:
        """``key 'space' at 2.0 s``."""
        what = self.kind.replace("_", " ") + (f" {self.name!r}" if self.name else "")
        return f"{what} at {self.at_ms / 1000:.1f} s"


class ExplorationEpisode(BaseModel):
    """One run of a program: its stimuli in time, the answers its questions get (in turn, round and round), the
    ``Math.random`` seed, and how long it lasts (virtual time)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    name: str
    """What makes it one of its plan's (``seed 2``, ``seed 3, answers: task numbers``)."""

    seed: int = Field(ge=0, lt=2**32)
    stimuli: list[Stimulus]
    answers: list[str] = Field(default_factory=list)
    span_ms: int = Field(gt=0, le=MAX_SPAN_MS)
    answer_delay_ms: int = Field(default=100, ge=0)

    @model_validator(mode="after")
    def _in_order(self) -> ExplorationEpisode:
        times = [stimulus.at_ms for stimulus in self.stimuli]
        if times != sorted(times) or (times and times[-1] > self.span_ms):
            raise ValueError(f"episode {self.name}: stimuli must be in time order, within its span")
        return self

    def timeline(self) -> dict[str, JsonValue]:
        """The page runner's arguments (``scratch-gui/explore/run.js``)."""
        stimuli: list[JsonValue] = [
            {"atMs": s.at_ms, "kind": s.kind, "name": s.name, "holdMs": s.hold_ms} for s in self.stimuli
        ]
        answers: list[JsonValue] = list(self.answers)
        return {"stimuli": stimuli, "answers": answers, "answerDelayMs": self.answer_delay_ms, "spanMs": self.span_ms}


class ExplorationPlan(BaseModel):
    """A task's episodes and its answer domain; the same for the golden and every variant of the task."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    episodes: list[ExplorationEpisode] = Field(max_length=MAX_EPISODES)
    answer_domain: AnswerDomain = "any"
    domain_source: str = ""
    """Where the domain comes from (the task's declaration, or the instruction's words), for the report."""

    def in_task(self, answers: list[str]) -> bool:
        """Whether every answer given is one the instruction allows."""
        return all(in_domain(answer, self.answer_domain) for answer in answers)
