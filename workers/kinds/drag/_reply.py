"""Read the one drag out of a model's reply to a drag task.

The asked-for answer is ``drag(start_point='<point>x y</point>', end_point='<point>x y</point>')``;
models write many near variants (other keywords and brackets, JSON, UI-TARS ``start_box``, bare
numbers, element indices), and a lenient reader measures grounding, not format discipline, as
upstream intends. After any ``<think>`` trace, the last complete drag call or JSON answer wins
(reasoning drafts earlier ones), then ``start: ... end: ...`` text, then the last two ``<point>``
tags. Points stay in the model's coordinates (the caller, which knows the convention, checks the
screen bounds); indices resolve to element centres in page px. Regexes are bounded or linear and
at most ``MAX_SCAN`` characters are read, so hostile replies stay cheap.
"""

from __future__ import annotations

import json
import math
import re
from collections.abc import Mapping
from typing import Any

from pydantic import BaseModel, ConfigDict

from workers.agent_api import DragParse
from workers.llm import repair_json

MAX_SCAN = 100_000
"""Characters read, from the end of the reply, where answers are."""

_MAX_OBJECT = 20_000
_MAX_REPAIR = 4_000
_MAX_OBJECTS = 64
_MAX_KEYWORDS = 64
_MAX_ARGS = 1_000
_MAX_VALUE = 300

_NUMBER = r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?"
_ITEM = re.compile(
    r"<index>\s*(?P<index>[^<]{0,40})</index>"
    r"|<point>(?P<point>[^<]{0,200})</point>"
    r"|\((?P<paren>[^()]{0,200})\)|\[(?P<bracket>[^\[\]]{0,200})\]|\{(?P<brace>[^{}]{0,200})\}"
    rf"|(?P<loose>{_NUMBER})",
    re.IGNORECASE,
)
_ROLES = r"start|from|source|src|begin|end|to|target|dest|destination|drop"
_PARTS = r"position|pos|point|box|coordinates|coordinate|coords|coord|location|index|idx|element|x|y"
_KEY = rf"(?:(?P<role>{_ROLES})(?:[ _-]?(?P<part>{_PARTS}))?|(?P<axis>[xy])_?(?P<num>[12]))"
_KEY_NAME = re.compile(_KEY, re.IGNORECASE)
_KEYWORD = re.compile(rf"(?<![\w]){_KEY}[\"'`*]*\s*[=:]", re.IGNORECASE)
_CALL = re.compile(r"\b(?:left_)?drag(?:_and_drop|_drop|_to|to)?\s*\(", re.IGNORECASE)
_THINK = re.compile(r"<(/?)think(?:ing)?>", re.IGNORECASE)
_CONTAINERS = frozenset({"args", "arguments", "parameters", "params", "action_inputs", "input", "inputs", "action"})

_End = int | tuple[float, float]
"""An answered point: an element index (int) or a point in the model's coordinates."""

_Parts = dict[tuple[str, str], float | _End]
"""What a reply gave per (role, part): role ``start``/``end``, part ``at`` (index or point), ``x``, ``y``."""


class ParsedDrag(BaseModel):
    """A reply read as one drag; on failure ``detail`` says why in one line."""

    model_config = ConfigDict(frozen=True)

    parse: DragParse
    start: tuple[float, float] | None = None
    """The press position: the model's coordinates, or page px when ``start_in_page``."""

    end: tuple[float, float] | None = None
    start_index: int | None = None
    end_index: int | None = None
    start_in_page: bool = False
    """``start`` is an element's centre in page px (the reply gave an index): do not convert it."""

    end_in_page: bool = False
    detail: str = ""


def parse_drag_reply(text: str, *, indices: Mapping[int, tuple[float, float]] | None = None) -> ParsedDrag:
    """The drag ``text`` answers; ``indices`` maps the shown element list's indices to centres in page px."""
    if not isinstance(text, str) or not text.strip():
        return ParsedDrag(parse="no_answer", detail="the reply is empty")
    text = text[-MAX_SCAN:]
    answer = _answer_part(text)
    found = _find(answer) if answer.strip() else None
    if found is None and answer != text:
        found = _find(text)
    if found is None:
        return ParsedDrag(parse="unparsed", detail="no drag with both a start and an end point was found")
    return _resolved(found[0], found[1], indices)


def _answer_part(text: str) -> str:
    """The reply without its reasoning trace: after the last ``</think>``, else before an unclosed ``<think>``."""
    tags = list(_THINK.finditer(text))
    closes = [tag for tag in tags if tag[1]]
    if closes:
        return text[closes[-1].end() :]
    return text[: tags[0].start()] if tags else text


def _find(text: str) -> tuple[_End, _End] | None:
    """The last complete drag call or JSON answer, else loose keywords, else the last two point/index tags."""
    calls = list(_CALL.finditer(text))[-_MAX_OBJECTS:]
    attempts = [(call.start(), _from_args, _call_args(text, call.end())) for call in calls]
    attempts += [(start, _from_json, text[start:end]) for start, end in _objects(text)]
    for _, read, body in sorted(attempts, key=lambda attempt: attempt[0], reverse=True):
        found = read(body)
        if found is not None:
            return found
    found = _from_keywords(text, last=True)
    if found is not None:
        return found
    tags = [_value(item) for item in _ITEM.finditer(text) if item["index"] is not None or item["point"] is not None]
    ends = [tag for tag in tags if tag is not None]
    return (ends[-2], ends[-1]) if len(ends) >= 2 else None


def _call_args(text: str, opened: int) -> str:
    """The text up to the parenthesis closing a call (bounded; a truncated call keeps what there is)."""
    depth = 1
    end = min(len(text), opened + _MAX_ARGS)
    for i in range(opened, end):
        if text[i] == "(":
            depth += 1
        elif text[i] == ")":
            depth -= 1
            if depth == 0:
                return text[opened:i]
    return text[opened:end]


def _from_args(args: str) -> tuple[_End, _End] | None:
    """A call's arguments: keywords when it has any, else two tags or brackets, two indices, or four numbers."""
    if _KEYWORD.search(args):
        return _from_keywords(args, last=False)
    items = list(_ITEM.finditer(args))
    if len(items) == 2 and items[0]["loose"] and items[1]["loose"]:  # drag(3, 7): two element indices
        first, second = _integer(float(items[0]["loose"])), _integer(float(items[1]["loose"]))
        return (first, second) if first is not None and second is not None else None
    ends: list[_End | None] = []
    pending: list[float] = []
    for item in items:
        if item["loose"] is None:
            ends.append(_value(item))
            continue
        pending.append(float(item["loose"]))
        if len(pending) == 2:  # loose numbers pair up: x, y
            ends.append(_point(pending))
            pending = []
    found = [end for end in ends if end is not None]
    return (found[0], found[1]) if len(found) >= 2 else None


def _from_keywords(text: str, *, last: bool) -> tuple[_End, _End] | None:
    """``key=value`` / ``key: value`` pairs, each value running to the next key; ``last``: later keys win
    (and only the last ``_MAX_KEYWORDS`` keys are read: a reply of endless keys stays cheap)."""
    matches = list(_KEYWORD.finditer(text))
    if last:
        matches = matches[-_MAX_KEYWORDS:]
    parts: _Parts = {}
    for i, match in enumerate(matches):
        stop = matches[i + 1].start() if i + 1 < len(matches) else len(text)
        role, part = _key(match)
        if not last and (role, part) in parts:
            continue
        value = _text_value(text[match.end() : min(stop, match.end() + _MAX_VALUE)], part)
        if value is not None:
            parts[(role, part)] = value
    return _assembled(parts)


def _key(match: re.Match[str]) -> tuple[str, str]:
    """(``start``/``end``, ``at``/``x``/``y``) for a matched key."""
    if match["axis"]:
        return ("start" if match["num"] == "1" else "end"), match["axis"].lower()
    role = "start" if match["role"].lower() in ("start", "from", "source", "src", "begin") else "end"
    part = (match["part"] or "").lower()
    return role, part if part in ("x", "y") else "at"


def _text_value(value: str, part: str) -> float | _End | None:
    """A value written as text: a tag or bracketed point first, else loose numbers (a pair, or one index)."""
    items = list(_ITEM.finditer(value))
    loose = [float(item["loose"]) for item in items if item["loose"] is not None]
    if part in ("x", "y"):
        return loose[0] if loose else None
    tagged = next((item for item in items if item["loose"] is None), None)
    if tagged is not None:
        return _value(tagged)
    if len(loose) >= 2:
        return _point(loose[:2])
    return _integer(loose[0]) if loose else None


def _value(item: re.Match[str]) -> _End | None:
    """One tag or bracket: an index, a point, or a box (x1, y1, x2, y2) taken at its centre."""
    if item["index"] is not None:
        numbers = _numbers(item["index"])
        return _integer(numbers[0]) if len(numbers) == 1 else None
    return _point(_numbers(item["point"] or item["paren"] or item["bracket"] or item["brace"] or ""))


def _point(numbers: list[float]) -> tuple[float, float] | None:
    """Two numbers, or a box's centre; None for other counts or a non-finite number (too many digits)."""
    if not all(math.isfinite(number) for number in numbers):
        return None
    if len(numbers) == 2:
        return numbers[0], numbers[1]
    if len(numbers) == 4:
        return (numbers[0] + numbers[2]) / 2, (numbers[1] + numbers[3]) / 2
    return None


def _objects(text: str) -> list[tuple[int, int]]:
    """Spans of the last balanced ``{...}`` (nested too) and a final unclosed one, in one linear pass
    (``workers.llm``'s scanner restarts at each brace); quotes count only inside braces."""
    found: list[tuple[int, int]] = []
    opened: list[int] = []
    quote = ""
    i = 0
    while i < len(text):
        char = text[i]
        if quote:
            if char == "\\":
                i += 1
            elif char == quote or (char == "\n" and quote == "'"):
                quote = ""
        elif char == "{":
            opened.append(i)
        elif char == "}" and opened:
            start = opened.pop()
            if i + 1 - start <= _MAX_OBJECT:
                found.append((start, i + 1))
        elif char in "\"'" and opened:
            quote = char
        i += 1
    if opened and len(text) - opened[0] <= _MAX_OBJECT:
        found.append((opened[0], len(text)))
    return found[-_MAX_OBJECTS:]


def _from_json(body: str) -> tuple[_End, _End] | None:
    """A JSON (or almost-JSON) object whose keys, or whose ``args``-like sub-object's keys, name both ends."""
    try:
        value = json.loads(body, strict=False)
    except (ValueError, RecursionError):
        try:  # repairing is Python-speed: only answer-sized objects
            value = json.loads(repair_json(body)) if len(body) <= _MAX_REPAIR else None
        except (ValueError, RecursionError):
            return None
    if not isinstance(value, dict):
        return None
    flat: dict[str, Any] = {}
    for key, item in value.items():
        if str(key).lower() in _CONTAINERS and isinstance(item, dict):
            flat.update(item)
        else:
            flat.setdefault(str(key), item)
    parts: _Parts = {}
    for key, item in flat.items():
        if (match := _KEY_NAME.fullmatch(key.strip())) and (found := _json_value(item, _key(match)[1])) is not None:
            parts[_key(match)] = found
    return _assembled(parts)


def _json_value(item: Any, part: str) -> float | _End | None:
    if isinstance(item, str):
        return _text_value(item[:_MAX_VALUE], part)
    if isinstance(item, dict):
        lowered = {str(key).lower(): value for key, value in item.items()}
        item = [lowered.get("x"), lowered.get("y")]
    if isinstance(item, list):
        numbers = [_json_number(number) for number in item]
        return None if None in numbers else _point(numbers)  # type: ignore[arg-type]
    number = _json_number(item)
    if number is None:
        return None
    return number if part in ("x", "y") else _integer(number)


def _assembled(parts: _Parts) -> tuple[_End, _End] | None:
    """Both ends from what was given: an index or point, else separate x and y."""
    ends: list[_End] = []
    for role in ("start", "end"):
        at, x, y = parts.get((role, "at")), parts.get((role, "x")), parts.get((role, "y"))
        if at is not None and not isinstance(at, float):
            ends.append(at)
        elif isinstance(x, float) and isinstance(y, float) and (point := _point([x, y])) is not None:
            ends.append(point)
        else:
            return None
    return ends[0], ends[1]


def _resolved(start: _End, end: _End, indices: Mapping[int, tuple[float, float]] | None) -> ParsedDrag:
    """The result, indices mapped to element centres (page px); an index not in the list is ``bad_index``."""
    fields: dict[str, Any] = {}
    problems: list[str] = []
    for role, answered in (("start", start), ("end", end)):
        centre = None if isinstance(answered, tuple) or indices is None else indices.get(answered)
        if isinstance(answered, tuple):
            fields[role] = answered
        elif centre is None:
            fields[f"{role}_index"] = answered
            problems.append(
                f"{role} index {answered}: "
                + ("no element list was shown" if indices is None else "not in the element list")
            )
        else:
            fields |= {role: (float(centre[0]), float(centre[1])), f"{role}_index": answered, f"{role}_in_page": True}
    return ParsedDrag(parse="bad_index" if problems else "ok", detail="; ".join(problems), **fields)


def _numbers(text: str) -> list[float]:
    return [float(found) for found in re.findall(_NUMBER, text)]


def _integer(number: float) -> int | None:
    """A plausible element index (a whole number from 0 to a million), else None."""
    return int(number) if 0 <= number <= 1e6 and number == int(number) else None


def _json_number(value: Any) -> float | None:
    """A JSON number (not a bool) as a float; None for anything else or an integer too big for a float."""
    if not isinstance(value, int | float) or isinstance(value, bool):
        return None
    try:
        return float(value)
    except OverflowError:
        return None
