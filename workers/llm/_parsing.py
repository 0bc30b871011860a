"""Read the action out of a model reply: ``Analysis: ...`` then one fenced JSON ``{"api": ..., "args": {...}}``.

Real replies stray from that format, so candidates are tried in order: fenced blocks tagged
json, other fenced blocks, then every balanced ``{...}`` in the text (a truncated one last);
the first candidate that parses, strictly or after ``repair_json``, to an object with ``"api"``
wins. Drafts inside ``<think>`` blocks are only used when the answer itself has none. A reply
with no usable action raises ``ReplyParseError`` whose message tells the model what to fix.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from typing import Any, Literal

from pydantic import BaseModel, JsonValue

from workers.contract import ScratchWorldError
from workers.llm._repair import repair_json

ParseFailure = Literal["no_json", "invalid_json", "missing_api", "bad_api", "bad_args"]
"""Why a reply could not be parsed."""


class ReplyParseError(ScratchWorldError):
    """A model reply holds no usable action; ``str(error)`` is written to be shown back to the model."""

    def __init__(self, reason: ParseFailure, message: str) -> None:
        super().__init__(message)
        self.reason: ParseFailure = reason


EXPECTED_FORMAT = (
    'Write "Analysis: <your reasoning>" and then exactly one fenced JSON block:\n'
    '```json\n{"api": "<action name>", "args": {"<name>": <value>}}\n```'
)
"""The format reminder appended to every parse error shown to the model."""

_FENCE = re.compile(r"```[ \t]*([\w+-]*)[^\n`]*\n?(.*?)(?:```|\Z)", re.DOTALL)
_JSON_TAGS = {"json", "json5", "jsonc"}
_THINK = re.compile(r"<think(?:ing)?>.*?</think(?:ing)?>", re.DOTALL | re.IGNORECASE)
_THINK_END = re.compile(r"</think(?:ing)?>", re.IGNORECASE)
_LABEL = re.compile(r"^\s*(?:#+\s*)?(?:\*\*)?analysis(?:\*\*)?\s*:\s*(?:\*\*)?\s*", re.IGNORECASE)
_MAX_CANDIDATES = 64


class ParsedReply(BaseModel):
    """The action a model asked for, and the reasoning it gave."""

    analysis: str
    """The reply's prose without the action block and without an ``Analysis:`` label."""

    request: dict[str, JsonValue]
    """The action: ``api`` (a non-empty string), ``args`` (an object, ``{}`` when omitted), and any extra keys."""

    @property
    def api(self) -> str:
        return str(self.request["api"])

    @property
    def args(self) -> dict[str, JsonValue]:
        args = self.request.get("args")
        return args if isinstance(args, dict) else {}


@dataclass(frozen=True)
class _Candidate:
    text: str
    span: tuple[int, int]
    """Where the candidate (or its whole fence) sits in the searched text; removed from the analysis."""


def parse_reply(text: str) -> ParsedReply:
    """Return the first action in ``text``; raise ``ReplyParseError`` (feedback for the model) when there is none."""
    answer = _answer_part(text)
    searches = [answer] if answer == text else [answer, text]
    failure: ReplyParseError | None = None
    for searched in searches:
        try:
            return _parse_in(searched)
        except ReplyParseError as error:
            failure = failure if failure is not None and failure.reason != "no_json" else error
    assert failure is not None
    raise failure


def _answer_part(text: str) -> str:
    """The reply without its reasoning trace (``<think>...</think>``, or all before a lone ``</think>``)."""
    stripped = _THINK.sub("", text)
    ends = list(_THINK_END.finditer(stripped))
    return stripped[ends[-1].end() :] if ends else stripped


def _parse_in(text: str) -> ParsedReply:
    first_error: str | None = None
    saw_object = False
    for candidate in _candidates(text):
        value, error = _load(candidate.text)
        if error is not None:
            if ":" in candidate.text:  # "{variable}" in prose is not an attempt at JSON
                first_error = first_error or error
            continue
        if not isinstance(value, dict):
            continue
        if "api" not in value:
            saw_object = True
            continue
        return _reply(value, _analysis(text, candidate.span))
    if saw_object:
        raise _error("missing_api", 'The JSON object in your reply has no "api" key naming the action.')
    if first_error is not None:
        raise _error("invalid_json", f"The JSON in your reply could not be parsed ({first_error}).")
    raise _error("no_json", "Your reply contains no JSON action.")


def _candidates(text: str) -> list[_Candidate]:
    fences = list(_FENCE.finditer(text))
    tagged = [fence for fence in fences if fence.group(1).lower() in _JSON_TAGS]
    others = [fence for fence in fences if fence.group(1).lower() not in _JSON_TAGS]
    found: list[_Candidate] = []
    for fence in tagged + others:
        body = fence.group(2)
        found.append(_Candidate(body.strip(), fence.span()))
        found.extend(_Candidate(obj, fence.span()) for obj, _ in _objects(body))
    found.extend(_Candidate(obj, span) for obj, span in _objects(text))
    return found[:_MAX_CANDIDATES]


def _objects(text: str) -> list[tuple[str, tuple[int, int]]]:
    """Every balanced ``{...}`` in order of its opening brace (nested ones too), then truncated ones."""
    closed: list[tuple[str, tuple[int, int]]] = []
    unclosed: list[tuple[str, tuple[int, int]]] = []
    start = text.find("{")
    for _ in range(4 * _MAX_CANDIDATES):
        if start < 0:
            break
        end = _balanced_end(text, start)
        if end is None:
            unclosed.append((text[start:], (start, len(text))))
        else:
            closed.append((text[start:end], (start, end)))
        start = text.find("{", start + 1)
    return closed + unclosed[:1]


def _balanced_end(text: str, start: int) -> int | None:
    """The index just past the brace that closes the one at ``start``; strings (either quote) are skipped."""
    depth = 0
    quote: str | None = None
    i = start
    while i < len(text):
        char = text[i]
        if quote is not None:
            if char == "\\":
                i += 1
            elif char == quote or (char == "\n" and quote == "'"):
                quote = None
        elif char in "\"'":
            quote = char
        elif char == "{":
            depth += 1
        elif char == "}":
            depth -= 1
            if depth == 0:
                return i + 1
        i += 1
    return None


def _load(candidate: str) -> tuple[Any, str | None]:
    """The parsed value, or None and the strict parser's complaint when even the repaired text fails."""
    try:
        return json.loads(candidate, strict=False), None
    except ValueError as exc:
        strict_error = (
            f"{exc.msg} at line {exc.lineno} column {exc.colno}" if isinstance(exc, json.JSONDecodeError) else str(exc)
        )
    try:
        return json.loads(repair_json(candidate)), None
    except (ValueError, RecursionError):
        return None, strict_error


def _reply(value: dict[str, Any], analysis: str) -> ParsedReply:
    api = value["api"]
    if not isinstance(api, str) or not api.strip():
        raise _error("bad_api", f'"api" must be a non-empty string naming the action, got {json.dumps(api)}.')
    args = value.get("args")
    if args is None:
        args = {}
    if not isinstance(args, dict):
        raise _error("bad_args", f'"args" must be a JSON object of named arguments, got {json.dumps(args)}.')
    request = {**value, "api": api.strip(), "args": args}
    return ParsedReply(analysis=analysis, request=request)


def _analysis(text: str, span: tuple[int, int]) -> str:
    before, after = text[: span[0]].strip(), text[span[1] :].strip()
    prose = "\n\n".join(part for part in (before, after) if part)
    return _LABEL.sub("", prose, count=1).strip()


def _error(reason: ParseFailure, problem: str) -> ReplyParseError:
    return ReplyParseError(reason, f"{problem}\n{EXPECTED_FORMAT}")
