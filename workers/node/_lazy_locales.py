"""The editor bundle's translations made on first use, in place (``install.sh`` runs this once).

The bundle carries every language's messages twice (the GUI's, from scratch-l10n, and scratch-blocks'
own) as object literals that each page builds as it starts: 80 languages, 6.9 MB of the bundle's
19 MB, where a page needs English unless someone picks another language. Each language but English
becomes a getter that builds its messages the first time they are read and then keeps them as a
plain property, so picking a language works as before. V8 compiles a getter only when it runs, so
an opening neither reads those literals from the code cache nor builds their objects.

    .venv/bin/python -m workers.node._lazy_locales BUNDLE
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from pathlib import Path

KEPT = "en"
"""The language a page starts in, built as before."""

_GUI_MESSAGES = re.compile(r'\{ab:\{"gui\.alerts\.lostPeripheralConnection":')
"""The GUI's messages by language, as the minified bundle writes them (the first language is ``ab``)."""
_GUI_DONE = 'get ab(){const v={"gui.alerts.lostPeripheralConnection":'
_BLOCKS_MESSAGES = re.compile(r'(?<=[},;])(\w+)\.locales(?:\.([\w$]+)|\["([^"]+)"\])=\{CONTROL_FOREVER:')
"""One language of scratch-blocks' messages: ``<ScratchMsgs>.locales.<language>={...}``."""
_BLOCKS_DONE = re.compile(r'Object\.defineProperty\(\w+\.locales,"ab",\{get\(\)\{const v=\{CONTROL_FOREVER:')
_KEY = re.compile(r'("[^"\\]+"|[A-Za-z_$][\w$]*):')


class LazyLocalesError(Exception):
    """The bundle does not have the translations where this bundle version has them."""


@dataclass(frozen=True)
class Rewritten:
    text: str
    languages: int
    """Languages made lazy (each counted once per message set)."""
    already: bool
    """The bundle had been rewritten before: nothing changed."""


def _literal_end(text: str, start: int) -> int:
    """The index after the object literal opening at ``start``. Only a messages literal is scanned, whose
    values are strings and objects, so strings are all that can hold a brace."""
    if text[start] != "{":
        raise LazyLocalesError(f"expected an object literal at {start}, found {text[start : start + 20]!r}")
    depth, index = 0, start
    while index < len(text):
        char = text[index]
        if char in "\"'`":
            index += 1
            while index < len(text) and text[index] != char:
                index += 2 if text[index] == "\\" else 1
        elif char == "{":
            depth += 1
        elif char == "}":
            depth -= 1
            if depth == 0:
                return index + 1
        index += 1
    raise LazyLocalesError(f"the object literal at {start} does not end")


def _keep_on_first_read(target: str, name: str, literal: str) -> str:
    """A getter's body: build the messages, put them in the getter's place, return them."""
    plain = "{value:v,writable:true,enumerable:true,configurable:true}"
    return f"{{const v={literal};Object.defineProperty({target},{name},{plain});return v}}"


def _gui_messages(text: str) -> tuple[str, int]:
    found = _GUI_MESSAGES.search(text)
    if found is None:
        return text, 0
    start = found.start()
    end = _literal_end(text, start)
    entries, index, lazy = [], start + 1, 0
    while text[index] != "}":
        key = _KEY.match(text, index)
        if key is None:
            raise LazyLocalesError(f"the GUI's messages have an entry that is not a language at {index}")
        value_end = _literal_end(text, key.end())
        name = key.group(1)
        if name.strip('"') == KEPT:
            entries.append(text[index:value_end])
        else:
            quoted = name if name.startswith('"') else f'"{name}"'
            entries.append(f"get {name}(){_keep_on_first_read('this', quoted, text[key.end() : value_end])}")
            lazy += 1
        index = value_end + (text[value_end] == ",")
    return text[:start] + "{" + ",".join(entries) + "}" + text[end:], lazy


def _blocks_messages(text: str) -> tuple[str, int]:
    parts, done, lazy = [], 0, 0
    for found in _BLOCKS_MESSAGES.finditer(text):
        if found.start() < done:
            continue
        owner, name = found.group(1), found.group(2) or found.group(3)
        value_start = found.end() - len("{CONTROL_FOREVER:")
        value_end = _literal_end(text, value_start)
        if text[value_end] not in ",;":
            raise LazyLocalesError(f"scratch-blocks' {name} messages are not a statement of their own")
        parts.append(text[done : found.start()])
        if name == KEPT:
            parts.append(text[found.start() : value_end])
        else:
            target = f"{owner}.locales"
            getter = _keep_on_first_read("this", f'"{name}"', text[value_start:value_end])
            parts.append(
                f'Object.defineProperty({target},"{name}",{{get(){getter},enumerable:true,configurable:true}})'
            )
            lazy += 1
        done = value_end
    parts.append(text[done:])
    return "".join(parts), lazy


def rewrite(text: str) -> Rewritten:
    """The bundle with every language but English built on first use; raises ``LazyLocalesError`` when
    either message set is found neither as it is published nor as this left it."""
    text, gui = _gui_messages(text)
    text, blocks = _blocks_messages(text)
    gui_done = gui > 0 or _GUI_DONE in text
    blocks_done = blocks > 0 or _BLOCKS_DONE.search(text) is not None
    if not (gui_done and blocks_done):
        missing = "the GUI's" if not gui_done else "scratch-blocks'"
        raise LazyLocalesError(f"{missing} translations are not where @scratch/scratch-gui-standalone 15.1.1 has them")
    return Rewritten(text=text, languages=gui + blocks, already=gui + blocks == 0)


def main(argv: list[str]) -> int:
    if len(argv) != 1:
        print("usage: python -m workers.node._lazy_locales BUNDLE", file=sys.stderr)
        return 2
    bundle = Path(argv[0])
    before = bundle.read_text(encoding="utf-8")
    try:
        result = rewrite(before)
    except LazyLocalesError as exc:
        print(f"lazy locales: {bundle}: {exc}", file=sys.stderr)
        return 1
    if not result.already:  # written beside, then moved: an interrupted install leaves the bundle whole
        rewritten = bundle.with_name(bundle.name + ".lazy")
        rewritten.write_text(result.text, encoding="utf-8")
        rewritten.replace(bundle)
    state = "already done" if result.already else f"{result.languages} message sets made lazy"
    print(f"lazy locales: {state} ({len(before):,} -> {len(result.text):,} characters)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
