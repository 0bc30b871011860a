"""A golden and its variant side by side: every script of both as pseudocode, what differs marked.

The pseudocode is the audit's own listing (``variants.script_listings``, which the report's before and after
come from). Scripts are paired by sprite and top block; a script that differs is marked, and
so are its lines that differ and, in both programs, the line that shows the changed block. Everything from
the projects is escaped: a project's names and texts are anybody's.
"""

from __future__ import annotations

import difflib
from collections.abc import Collection
from html import escape
from typing import Any

from scratchworld_dist.kinds.audit.variants import Listings, ScriptText, script_listings

Key = tuple[str, str]
"""(target, top block) of a script."""


def programs_html(golden: dict[str, Any], variant: dict[str, Any] | None, place: Key | None, label: str) -> str:
    """A table of the golden's scripts beside the variant's (``label`` heads its column; None: the golden
    alone), ``place`` (target, block) the block the variant changed."""
    old = script_listings(golden)
    new = script_listings(variant) if variant is not None else None
    columns = 1 if new is None else 2
    head = "<th>golden</th>" + ("" if new is None else f"<th>{escape(label)}</th>")
    differing = 0 if new is None else sum(1 for key in {**old, **new} if not _same(old.get(key), new.get(key)))
    body: list[str] = []
    for target, heading in _targets(golden, variant):
        body.append(f'<tr class="target"><th colspan="{columns}">{escape(heading)}</th></tr>')
        keys = _keys(old, target) + [k for k in _keys(new or {}, target) if k not in old]
        if not keys:
            body.append(f'<tr><td colspan="{columns}" class="absent">(no scripts)</td></tr>')
        for key in keys:
            body.append(_row(key, old.get(key), None if new is None else new.get(key), new is not None, place))
    summary = (
        "" if new is None else f'<p class="sub">{differing} script(s) differ, marked; the changed block is marked.</p>'
    )
    return (
        f'{summary}<table class="audit-programs columns-{columns}">\n<thead><tr>{head}</tr></thead>\n'
        f"<tbody>\n{chr(10).join(body)}\n</tbody></table>"
    )


def _targets(golden: dict[str, Any], variant: dict[str, Any] | None) -> list[tuple[str, str]]:
    """(name, heading) of every target of either program: the golden's in its order, then the variant's new ones."""
    found: dict[str, str] = {}
    for project in (golden, variant or {}):
        for target in project.get("targets", []):
            if isinstance(target, dict):
                name = str(target.get("name"))
                found.setdefault(name, "Stage" if target.get("isStage") else f"Sprite: {name}")
    return list(found.items())


def _keys(scripts: Listings, target: str) -> list[Key]:
    return sorted((key for key in scripts if key[0] == target), key=lambda key: scripts[key].rank)


def _same(a: ScriptText | None, b: ScriptText | None) -> bool:
    return a is not None and a.same(b)


def _row(key: Key, old: ScriptText | None, new: ScriptText | None, paired: bool, place: Key | None) -> str:
    changed = paired and not _same(old, new)
    old_lines, new_lines = _differing_lines(old, new) if changed else (set(), set())
    block = place[1] if place is not None and place[0] == key[0] else None
    cells = [_cell(old, old_lines, block)]
    if paired:
        cells.append(_cell(new, new_lines, block))
    return f'<tr class="script{" changed" if changed else ""}">{"".join(cells)}</tr>'


def _differing_lines(old: ScriptText | None, new: ScriptText | None) -> tuple[set[int], set[int]]:
    """Indices of the lines that differ, in each (every line of a script the other program lacks)."""
    if old is None or new is None:
        return set(range(len(old.lines) if old else 0)), set(range(len(new.lines) if new else 0))
    ours, theirs = set(), set()
    for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(None, old.lines, new.lines, autojunk=False).get_opcodes():
        if tag != "equal":
            ours.update(range(i1, i2))
            theirs.update(range(j1, j2))
    return ours, theirs


def _cell(script: ScriptText | None, differing: Collection[int], block: str | None) -> str:
    if script is None:
        return '<td class="absent">(not in this program)</td>'
    lines = [f'<span class="head">{escape(script.head)}, script {script.rank}</span>']
    for index, text in enumerate(script.lines):
        shown = script.blocks[index] if index < len(script.blocks) else frozenset()
        line = escape(text)
        if block is not None and block in shown:
            line = f'<mark class="changed-block" title="the changed block">{line}</mark>'
        lines.append(f'<span class="line changed">{line}</span>' if index in differing else line)
    return f'<td><pre class="listing">{chr(10).join(lines)}</pre></td>'
