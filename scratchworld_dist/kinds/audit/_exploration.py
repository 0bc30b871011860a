"""A task's exploration plan, made from its golden and its instruction, independent of its tests: the green flag,
then every key, sprite click, stage click, backdrop switch and broadcast the golden's hat blocks listen to (and
the keys its ``key pressed?`` blocks read), one after another; answers to its questions from a small set the
task suggests (the numbers and quoted words of its instruction, a few generic numbers and words, and the empty
answer), each set its own episode with its own ``Math.random`` seed (a program that asks nothing gets a few seeds);
a fixed span of virtual time. The answer domain (which answers the instruction allows) is the task's declaration,
else what the instruction's words say it asks for, else any answer.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from workers.kinds.audit import AnswerDomain, ExplorationEpisode, ExplorationPlan, Stimulus

SETTLE_MS = 1500
"""The first input after the green flag (the program has set itself up)."""

GAP_MS = 700
"""Between two inputs."""

HOLD_MS = 300
"""How long a key is held."""

TAIL_MS = 3000
"""After the last input, before the episode ends."""

SPAN_MS = 8000
"""An episode lasts at least this long (virtual time)."""

SEEDS = (1, 2, 3)
"""The seeds of a program that asks nothing (the tests' own run has seed 0)."""

GENERIC_NUMBERS = ("5", "-2", "0.5")
GENERIC_WORDS = ("hello", "Scratch")
MAX_TASK_ANSWERS = 8
"""At most this many numbers (and quoted texts) from the instruction, in its order."""

ANY_KEY = "space"
"""The key pressed for a hat that listens to any key."""

_NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?![\w])")
_QUOTED = re.compile(r"\"([^\"\n]{1,40})\"|\u201c([^\u201d\n]{1,40})\u201d")
_ASKS = re.compile(r"\bask(?:s|ed|ing)?\b([^.,;:!?()]{0,60})", re.IGNORECASE)
_WHAT = (
    ("integers", re.compile(r"\b(whole numbers?|integers?)\b", re.IGNORECASE)),
    ("numbers", re.compile(r"\bnumbers?\b", re.IGNORECASE)),
    ("words", re.compile(r"\b(words?|names?)\b", re.IGNORECASE)),
)


@dataclass
class ProgramInputs:
    """What a program listens to, in the order its blocks name it."""

    keys: list[str] = field(default_factory=list)
    clicks: list[str] = field(default_factory=list)
    stage_click: bool = False
    backdrops: list[str] = field(default_factory=list)
    messages: list[str] = field(default_factory=list)
    asks: bool = False


def _blocks(project: dict[str, Any]) -> Iterator[tuple[dict[str, Any], dict[str, Any]]]:
    for target in project.get("targets", []):
        if not isinstance(target, dict):
            continue
        for block in (target.get("blocks") or {}).values():
            if isinstance(block, dict):
                yield target, block


def _field(block: dict[str, Any], name: str) -> str | None:
    value = (block.get("fields") or {}).get(name)
    return str(value[0]) if isinstance(value, list) and value and value[0] is not None else None


def program_inputs(project: dict[str, Any]) -> ProgramInputs:
    """The stimuli ``project``'s hat blocks listen to (and the keys its ``key pressed?`` blocks read)."""
    found = ProgramInputs()

    def add(into: list[str], value: str | None) -> None:
        if value is not None and value not in into:
            into.append(value)

    for target, block in _blocks(project):
        opcode = block.get("opcode")
        if opcode in ("event_whenkeypressed", "sensing_keyoptions"):
            key = _field(block, "KEY_OPTION")
            add(found.keys, ANY_KEY if key == "any" else key)
        elif opcode == "event_whenthisspriteclicked" and not target.get("isStage"):
            add(found.clicks, str(target.get("name")))
        elif opcode == "event_whenstageclicked":
            found.stage_click = True
        elif opcode == "event_whenbackdropswitchesto":
            add(found.backdrops, _field(block, "BACKDROP"))
        elif opcode == "event_whenbroadcastreceived":
            add(found.messages, _field(block, "BROADCAST_OPTION"))
        elif opcode == "sensing_askandwait":
            found.asks = True
    return found


def timeline(inputs: ProgramInputs) -> tuple[list[Stimulus], int]:
    """The stimuli in time (the flag first, then each input in turn) and the episode's span."""
    stimuli = [Stimulus(at_ms=0, kind="green_flag")]
    todo: list[tuple[str, str]] = [
        *(("key", key) for key in inputs.keys),
        *(("click", name) for name in inputs.clicks),
        *([("stage_click", "")] if inputs.stage_click else []),
        *(("backdrop", name) for name in inputs.backdrops),
        *(("broadcast", name) for name in inputs.messages),
    ]
    for index, (kind, name) in enumerate(todo):
        hold = HOLD_MS if kind == "key" else 0
        stimuli.append(Stimulus(at_ms=SETTLE_MS + index * GAP_MS, kind=kind, name=name, hold_ms=hold))  # type: ignore[arg-type]
    return stimuli, max(SPAN_MS, stimuli[-1].at_ms + TAIL_MS)


def instruction_answers(instruction: str) -> tuple[list[str], list[str]]:
    """The numbers and the quoted texts of an instruction, in its order (at most ``MAX_TASK_ANSWERS`` each)."""
    numbers = list(dict.fromkeys(_NUMBER.findall(instruction)))[:MAX_TASK_ANSWERS]
    quoted = [a or b for a, b in _QUOTED.findall(instruction)]
    words = list(dict.fromkeys(text.strip() for text in quoted if text.strip()))[:MAX_TASK_ANSWERS]
    return numbers, words


def answer_domain_from(instruction: str) -> tuple[AnswerDomain, str] | None:
    """What the instruction says its questions ask for (``asks for two numbers``: numbers), with the words that
    say it; None when it names no kind of answer, or more than one."""
    kinds: dict[str, str] = {}
    for asked in _ASKS.finditer(instruction):
        for kind, pattern in _WHAT:
            if pattern.search(asked.group(1)):
                kinds.setdefault(kind, asked.group(0).strip())
                break
    if "integers" in kinds and "numbers" in kinds:
        kinds.pop("integers")  # a whole number among numbers: numbers
    if len(kinds) != 1:
        return None
    ((kind, words),) = kinds.items()
    return kind, words  # type: ignore[return-value]


def answer_sets(instruction: str) -> list[tuple[str, list[str]]]:
    """The episodes' answers for a program that asks: named sets, in order."""
    numbers, words = instruction_answers(instruction)
    sets: list[tuple[str, list[str]]] = []
    if numbers:
        sets.append(("task numbers", numbers))
        if len(numbers) > 1:
            sets.append(("task numbers reversed", numbers[::-1]))
    if words:
        sets.append(("task words", words))
    sets += [("generic numbers", list(GENERIC_NUMBERS)), ("generic words", list(GENERIC_WORDS)), ("empty", [""])]
    return sets


def exploration_plan(
    project: dict[str, Any], instruction: str, declared: AnswerDomain | None = None, declared_in: str = ""
) -> ExplorationPlan:
    """The task's plan: ``project`` is its golden; ``declared`` its declared answer domain (``declared_in`` the
    file), which the instruction's words only stand in for."""
    inputs = program_inputs(project)
    stimuli, span = timeline(inputs)
    if inputs.asks:
        episodes = [
            ExplorationEpisode(
                name=f"seed {seed}, answers: {name}", seed=seed, stimuli=stimuli, answers=answers, span_ms=span
            )
            for seed, (name, answers) in enumerate(answer_sets(instruction), start=1)
        ]
    else:
        episodes = [ExplorationEpisode(name=f"seed {seed}", seed=seed, stimuli=stimuli, span_ms=span) for seed in SEEDS]
    if declared is not None:
        domain, source = declared, f"declared in {declared_in}" if declared_in else "declared"
    elif (said := answer_domain_from(instruction)) is not None:
        domain, source = said[0], f"the instruction says {said[1]!r}"
    else:
        domain, source = "any", "the instruction names no kind of answer"
    return ExplorationPlan(episodes=episodes, answer_domain=domain, domain_source=source)
