"""What a suite declares its instructions leave open, for the grader audit: per task, the answers its questions
allow (``answers``: the answer domain, so a difference only other answers show is outside the task) and the
holes it explains (``explained``: a reason and a matcher a hole must match; the report scores on the others).

Our suite's layout keeps them next to each task (``<category>/<task>/audit.yaml``); an upstream clone's, whose
data this repository never writes into, in ONE file beside it (``audit.explanations`` in a config, ``--explanations``
on the command line; ``configs/audit/upstream.yaml`` by default):

```yaml
answers: numbers                 # any | text | numbers | integers | words
explained:
  - reason: the instruction asks for a question, not its wording
    match: {block: sensing_askandwait, input: QUESTION, change: "-> '.+'"}
```

A matcher's keys (each given one must match): ``operator``, ``target`` (the sprite changed), ``block`` (the changed
block's opcode or id), ``input`` (its input or field), ``change`` (a regular expression found in the change, as
``QUESTION: 'a' -> 'b'``), ``difference`` (the first difference's trace field; ``var``: any variable's),
``variable`` (that variable's name).

and, in the one file of a clone, the same under each task's id: ``tasks: {<task_id>: {answers: ..., explained: ...}}``.
A bad file fails with one line naming it and the first problem.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from scratchworld_dist._errors import SuiteError, validation_summary
from scratchworld_dist.kinds.audit.variants import OPERATORS, REFACTORINGS
from scratchworld_dist.suites import Suite
from workers.kinds.audit import AnswerDomain

TASK_FILE = "audit.yaml"
"""A task's declarations in our suite's layout, next to its task.json."""

DEFAULT_UPSTREAM_FILE = Path(__file__).resolve().parents[3] / "configs" / "audit" / "upstream.yaml"
"""The declarations shipped for the upstream benchmark (used for an upstream clone unless a config names one)."""

_INPUT = re.compile(r"^([A-Z][A-Z0-9_]*): ")


class HoleMatcher(BaseModel):
    """What a hole must be to be explained: every key given must match (at least one is)."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    operator: str | None = None
    """The mutation operator (``text_literal``, ``number_literal``...)."""

    target: str | None = None
    """The sprite (or ``Stage``) whose script was changed."""

    block: str | None = None
    """The changed block: its opcode (``sensing_askandwait``) or its id."""

    input: str | None = None
    """The block's input or field the change is in (``QUESTION``, ``STEPS``)."""

    change: str | None = None
    """A regular expression the change must contain a match of (``STEPS: 20 -> 2[01]``, as the report words it)."""

    difference: str | None = None
    """The first observable difference's trace field (``bubble``, ``question``, ``x``...; ``var``: any variable)."""

    variable: str | None = None
    """The variable the first difference is in, by name."""

    @model_validator(mode="after")
    def _says_something(self) -> HoleMatcher:
        if all(value is None for value in self.model_dump().values()):
            raise ValueError(f"a matcher needs at least one of {', '.join(type(self).model_fields)}")
        if self.change is not None:
            try:
                re.compile(self.change)
            except re.error as exc:
                raise ValueError(f"change is no regular expression: {exc}") from None
        known = {*OPERATORS, *REFACTORINGS}
        if self.operator is not None and self.operator not in known:
            raise ValueError(f"unknown operator {self.operator!r} (operators: {', '.join(sorted(known))})")
        return self

    def matches(self, hole: HoleFacts) -> bool:
        return (
            _same(self.operator, hole.operator)
            and _same(self.target, hole.target)
            and (self.block is None or self.block in (hole.block_opcode, hole.block_id))
            and _same(self.input, hole.input)
            and (self.change is None or re.search(self.change, hole.change) is not None)
            and (self.difference is None or _field_matches(self.difference, hole.difference))
            and _same(self.variable, hole.variable)
        )


def _same(wanted: str | None, value: str | None) -> bool:
    return wanted is None or wanted == value


def _field_matches(wanted: str, field: str | None) -> bool:
    if field is None:
        return False
    if wanted == "var":
        return field.startswith("var:")
    return field == wanted or field.split(".", 1)[0] == wanted


class ExplainedHole(BaseModel):
    model_config = ConfigDict(frozen=True, extra="forbid")

    reason: str = Field(min_length=1)
    """Why this difference is no wrong answer to the task (for people; the report shows it)."""

    match: HoleMatcher


class TaskDeclarations(BaseModel):
    """One task's declarations."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    answers: AnswerDomain | None = None
    """The answers its questions allow (None: what the instruction's words say, else any)."""

    explained: list[ExplainedHole] = Field(default_factory=list)

    source: str = Field(default="", exclude=True)
    """The file they were read from (for messages and the report)."""

    def explanation(self, hole: HoleFacts) -> ExplainedHole | None:
        """The first declaration that explains ``hole``."""
        return next((entry for entry in self.explained if entry.match.matches(hole)), None)


class SuiteDeclarations(BaseModel):
    """An upstream clone's one file."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    tasks: dict[str, TaskDeclarations] = Field(default_factory=dict)


class HoleFacts(BaseModel):
    """What a hole's matcher is matched against: the change and the first observable difference."""

    operator: str
    target: str
    block_id: str
    block_opcode: str = ""
    change: str = ""
    difference: str | None = None
    """The trace field of the first difference."""

    variable: str | None = None

    @property
    def input(self) -> str | None:
        """The changed input of a literal's change (``QUESTION: 'a' -> 'b'``)."""
        found = _INPUT.match(self.change)
        return found.group(1) if found else None


def _read(path: Path) -> Any:
    try:
        return yaml.safe_load(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise SuiteError(f"cannot read the audit declarations: {exc.strerror or exc}", path) from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" (line {mark.line + 1})" if mark is not None else ""
        raise SuiteError(f"not YAML{where}", path) from None


def _validated(model: type[TaskDeclarations] | type[SuiteDeclarations], data: Any, path: Path) -> Any:
    if not isinstance(data, dict):
        raise SuiteError("the audit declarations must be a mapping", path)
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        raise SuiteError(f"bad audit declarations: {validation_summary(exc, limit=1)}", path) from None


def read_task_declarations(path: Path) -> TaskDeclarations:
    """One task's file (``SuiteError``, one line, when it is not a valid one)."""
    found: TaskDeclarations = _validated(TaskDeclarations, _read(path), path)
    return found.model_copy(update={"source": str(path)})


def read_suite_declarations(path: Path, task_ids: set[str] | None = None) -> dict[str, TaskDeclarations]:
    """A clone's one file (every task it names one of ``task_ids``, when given: a typo is no silent no-op)."""
    found: SuiteDeclarations = _validated(SuiteDeclarations, _read(path), path)
    unknown = sorted(set(found.tasks) - task_ids) if task_ids is not None else []
    if unknown:
        raise SuiteError(f"bad audit declarations: tasks.{unknown[0]}: the suite has no such task", path)
    return {task: entry.model_copy(update={"source": f"{path} (tasks.{task})"}) for task, entry in found.tasks.items()}


def suite_declarations(suite: Suite, explanations: Path | None = None) -> dict[str, TaskDeclarations]:
    """Every task's declarations: ``explanations`` (one file) when given, else each task's own file in our
    layout, or the shipped file for an upstream clone."""
    if explanations is not None:
        return read_suite_declarations(explanations, {task.id for task in suite.tasks})
    if suite.kind == "upstream":
        if DEFAULT_UPSTREAM_FILE.is_file():  # the benchmark's tasks: a clone's task list may hold fewer
            return read_suite_declarations(DEFAULT_UPSTREAM_FILE)
        return {}
    found = {}
    for task in suite.tasks:
        path = suite.root / task.category / task.id / TASK_FILE
        if path.is_file():
            found[task.id] = read_task_declarations(path)
    return found
