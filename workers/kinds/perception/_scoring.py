"""Judging a reply to a perception item, two ways: upstream's strict equality and our normalized reading.

``strict`` reproduces upstream: the reply, stripped, must equal the answer; YES/NO case-insensitively,
values exactly, so "YES." and "Yes, it is." fail. It measures format discipline as much as perception.

``normalized`` reads the final answer out of the reply first: after any ``<think>`` trace, the text after
the last "answer:" / "answer is" marker, else the last line (else the first line that opens with YES or
NO, for yes/no items); then trims Markdown emphasis, quotes and trailing punctuation. A quoted span in it
(`` `left arrow` ``, "apple") is taken as the value. YES/NO are matched as words, numbers are compared as
numbers (``10.0`` equals ``10``, a Unicode minus is a minus), dropdown options case-insensitively, text
exactly (a sentence's closing period aside). Only the last ``MAX_SCAN`` characters are read and every
pattern is linear, so a hostile reply stays cheap.
"""

from __future__ import annotations

import math
import re

from workers.agent_api import AnswerFormat, ValueKind
from workers.kinds.perception._contract import AnswerParse, PerceptionScore

MAX_SCAN = 20_000
"""Characters read, from the end of the reply, where answers are."""

_THINK = re.compile(r"<(/?)think(?:ing)?>", re.IGNORECASE)
_MARKER = re.compile(r"\b(?:final\s+)?answer\b\s*(?:is\b\s*:?|[:=\uff1a])", re.IGNORECASE)
_YES_NO = re.compile(r"(?<![\w'])(yes|no)(?![\w'])", re.IGNORECASE)
_NUMBER = re.compile(r"(?<![\w.])[-+]?\d+(?:\.\d+)?(?![\w])")
_QUOTED = re.compile(
    "`([^`\n]{1,200})`|\"([^\"\n]{1,200})\"|\u201c([^\u201d\n]{1,200})\u201d|(?<!\\w)'([^'\n]{1,200})'(?!\\w)"
    "|\u2018([^\u2019\n]{1,200})\u2019"
)
_EMPHASIS = re.compile(r"[*_]{1,3}")
_WRAPPERS = "\"'`\u201c\u201d\u2018\u2019\u00ab\u00bb()[]"
_CLOSING = ".!?,;:"
_MINUSES = str.maketrans({"\u2212": "-", "\u2012": "-", "\u2013": "-", "\u2014": "-", "\ufe63": "-", "\uff0d": "-"})


def strict_correct(reply: str, answer: str, answer_format: AnswerFormat) -> bool:
    """Upstream's rule: equality after ``strip()``, case-insensitive for YES/NO only."""
    given, expected = reply.strip(), answer.strip()
    return given.upper() == expected.upper() if answer_format == "yes_no" else given == expected


def score_reply(reply: str, answer: str, answer_format: AnswerFormat, value_kind: ValueKind | None) -> PerceptionScore:
    """Both scorings of ``reply`` against ``answer`` (``value_kind`` is required for value items)."""
    strict = strict_correct(reply, answer, answer_format)
    if not reply.strip():
        return PerceptionScore(strict=strict, normalized=False, extracted=None, parse="no_answer")
    text = _answer_part(reply[-MAX_SCAN:])
    if answer_format == "yes_no":
        extracted = _yes_no(text)
        return _scored(strict, extracted, extracted == answer.upper())
    kind = value_kind or "text"
    segment = _segment(text)
    if kind == "number":
        number = _number(segment)
        expected = _as_number(answer)
        if number is None:
            return _scored(strict, None, False)
        same = expected is not None and math.isclose(float(number), expected, rel_tol=0, abs_tol=1e-9)
        return _scored(strict, number, same if expected is not None else number == answer.strip())
    value = _value(segment)
    if not value:
        return _scored(strict, None, False)
    if kind == "dropdown":
        option = _trimmed(value)
        return _scored(strict, option, _folded(option) == _folded(_trimmed(answer)))
    expected_text = answer.strip()
    same = value == expected_text or (
        value.endswith(".") and not expected_text.endswith(".") and value[:-1] == expected_text
    )
    return _scored(strict, value, same)


def _scored(strict: bool, extracted: str | None, correct: bool) -> PerceptionScore:
    parse: AnswerParse = "ok" if extracted is not None else "unparsed"
    return PerceptionScore(
        strict=strict, normalized=correct and extracted is not None, extracted=extracted, parse=parse
    )


def _answer_part(text: str) -> str:
    """The reply without its reasoning trace: after the last ``</think>``, else before an unclosed ``<think>``."""
    tags = list(_THINK.finditer(text))
    closes = [tag for tag in tags if tag[1]]
    if closes:
        return text[closes[-1].end() :]
    return text[: tags[0].start()] if tags else text


def _lines(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip()]


def _segment(text: str) -> str:
    """Where the final answer is: after the last answer marker (to the end of its line), else the last line."""
    markers = list(_MARKER.finditer(text))
    if markers:
        rest = text[markers[-1].end() :]
        tail = _lines(rest)
        if tail:
            return tail[0]
    lines = _lines(text)
    return lines[-1] if lines else ""


def _yes_no(text: str) -> str | None:
    """YES or NO: the first such word of the answer segment, else of the first line that opens with one."""
    found = _YES_NO.search(_EMPHASIS.sub("", _segment(text)))
    if found is not None:
        return found[1].upper()
    for line in _lines(text):
        opening = _YES_NO.match(_trimmed(_EMPHASIS.sub("", line)))
        if opening is not None:
            return opening[1].upper()
    return None


def _number(segment: str) -> str | None:
    """The segment as a number when it is one, else its last number (prose ends on its answer)."""
    text = _trimmed(_EMPHASIS.sub("", segment)).translate(_MINUSES)
    if _as_number(text) is not None:
        return _canonical(text)
    quoted = [q for q in _quoted(text) if _as_number(q) is not None]
    if quoted:
        return _canonical(quoted[-1])
    numbers = _NUMBER.findall(text)
    return _canonical(numbers[-1]) if numbers else None


def _value(segment: str) -> str:
    """A text or option value: the last quoted span of the segment, else the segment, trimmed."""
    text = _EMPHASIS.sub("", segment).strip()
    quoted = _quoted(text)
    return quoted[-1].strip() if quoted else _trimmed(text, closing="")


def _quoted(text: str) -> list[str]:
    return [next(group for group in match.groups() if group is not None) for match in _QUOTED.finditer(text)]


def _trimmed(text: str, closing: str = _CLOSING) -> str:
    """Without surrounding whitespace, quotes and brackets, and (by default) closing punctuation."""
    previous = None
    while previous != text:
        previous = text
        text = text.strip().strip(_WRAPPERS).rstrip(closing).strip()
    return text


def _folded(text: str) -> str:
    return " ".join(text.casefold().split())


def _as_number(text: str) -> float | None:
    try:
        value = float(text.strip().translate(_MINUSES))
    except ValueError:
        return None
    return value if math.isfinite(value) else None


def _canonical(number: str) -> str:
    """The number as written, with a plain minus and no plus sign."""
    return number.strip().translate(_MINUSES).lstrip("+")
