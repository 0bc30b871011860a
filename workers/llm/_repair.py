"""Turn the almost-JSON that models write into JSON.

A small tokenizer re-emits the text as strict JSON, fixing what models commonly get wrong:
single-quoted strings, unquoted keys and bare words, Python's ``True``/``False``/``None``,
``//``, ``/* */`` and ``#`` comments, trailing commas, missing commas between items, raw
newlines inside strings, and brackets left open at the end. A string left open (a reply cut
off mid-argument) is refused rather than completed with a guess.
Anything it cannot tokenize raises ``ValueError``.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator

_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_IDENT = re.compile(r"[A-Za-z_$][\w$]*")
_LITERALS = {"true": "true", "false": "false", "null": "null", "True": "true", "False": "false", "None": "null"}
_CLOSER = {"{": "}", "[": "]"}
_VALUE_END = ("string", "number", "literal", "}", "]")
_VALUE_START = ("string", "number", "literal", "{", "[")


def repair_json(text: str) -> str:
    """Return ``text`` rewritten as strict JSON text; raise ``ValueError`` where it cannot be."""
    out: list[str] = []
    stack: list[str] = []
    previous = ""
    for kind, token in _tokens(text):
        if kind in ("}", "]"):
            if not stack or _CLOSER[stack[-1]] != kind:
                raise ValueError(f"unbalanced {kind!r}")
            stack.pop()
            if previous == ",":
                out.pop()  # trailing comma
        elif kind in _VALUE_START and previous in _VALUE_END:
            out.append(",")  # missing comma between items
        elif kind == "," and previous in ("", ",", "{", "[", ":"):
            continue  # stray or doubled comma
        if kind in ("{", "["):
            stack.append(kind)
        out.append(token)
        previous = kind
        if not stack and kind in ("}", "]"):
            break  # one value only; whatever follows is prose
    if previous == ",":
        out.pop()
    if previous == ":":
        out.append("null")
    out.extend(_CLOSER[opener] for opener in reversed(stack))
    return "".join(out)


def _tokens(text: str) -> Iterator[tuple[str, str]]:
    """Yield (kind, JSON text) pairs lazily (prose after the value is never read); kinds are
    punctuation, string, number and literal."""
    i, n = 0, len(text)
    while i < n:
        char = text[i]
        if char.isspace():
            i += 1
        elif text.startswith("//", i) or char == "#":
            end = text.find("\n", i)
            i = n if end < 0 else end + 1
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            i = n if end < 0 else end + 2
        elif char in "{}[]:,":
            yield char, char
            i += 1
        elif char in "\"'":
            value, i = _read_string(text, i)
            yield "string", json.dumps(value, ensure_ascii=False)
        elif match := _NUMBER.match(text, i):
            raw = match.group()
            number: float | int = float(raw) if any(c in raw for c in ".eE") else int(raw)
            yield "number", json.dumps(number)
            i = match.end()
        elif match := _IDENT.match(text, i):
            word = match.group()
            if word in _LITERALS:
                yield "literal", _LITERALS[word]
            else:
                yield "string", json.dumps(word)  # an unquoted key or bare word
            i = match.end()
        else:
            raise ValueError(f"unexpected character {char!r} at offset {i}")


_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", "b": "\b", "f": "\f", "/": "/", "\\": "\\", '"': '"', "'": "'"}


def _read_string(text: str, start: int) -> tuple[str, int]:
    """Read a quoted string starting at ``start``; an unterminated one is refused, not guessed at."""
    quote = text[start]
    chars: list[str] = []
    i, n = start + 1, len(text)
    while i < n:
        char = text[i]
        if char == quote:
            return "".join(chars), i + 1
        if char == "\\" and i + 1 < n:
            escaped = text[i + 1]
            if escaped == "u" and re.fullmatch(r"[0-9a-fA-F]{4}", text[i + 2 : i + 6]):
                chars.append(chr(int(text[i + 2 : i + 6], 16)))
                i += 6
                continue
            chars.append(_ESCAPES.get(escaped, "\\" + escaped))
            i += 2
            continue
        chars.append(char)
        i += 1
    raise ValueError("unterminated string (a truncated reply?)")
