"""Upstream's strict scoring against our normalized one, on canned replies to the perception items.

Two sets of replies per item:

- **Reply styles**: the item's own answer (or a wrong one) written the ways models write it: bare, lower case,
  with a closing period, in Markdown bold, after an ``Answer:`` line under some analysis, as a sentence, quoted,
  with a Unicode minus or a decimal point for numbers. A right answer in any style should count, a wrong one never.
- **Upstream's generator replies**: each upstream task file keeps the reply of the model that wrote the
  question ("Analysis: ... Question: ... Answer: YES"), a real model's text ending on the label it chose. It
  is not an answer to our prompt, but it is what models write when not held to one line.

Prints, per style, the accuracy each scoring gives and how often they disagree; the strict scoring should
agree with the normalized one only on bare answers. (Lower-casing a text value makes another text, which
both scorings rightly fail; a dropdown option lower-cased is still the option for the normalized one.)

Run: ``.venv/bin/python benchmarks/perception_scoring.py [UPSTREAM_DIR]`` (default ``../shared/scratchworld-upstream``).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from pathlib import Path

from scratchworld_dist.kinds.perception.items import PerceptionItem, load_perception_suite
from scratchworld_dist.kinds.perception.items._upstream import TASKS_DIR
from workers.kinds.perception import score_reply

Style = Callable[[str], str]

STYLES: dict[str, Style] = {
    "bare": lambda a: a,
    "lower case": lambda a: a.lower(),
    "closing period": lambda a: f"{a}.",
    "markdown bold": lambda a: f"**{a}**",
    "analysis, then Answer:": lambda a: f"The blocks line up and the field is readable.\nAnswer: {a}",
    "sentence": lambda a: f"The answer is {a}.",
    "quoted": lambda a: f"`{a}`",
}


def wrong(item: PerceptionItem) -> str:
    """A wrong answer of the right form."""
    if item.answer_format == "yes_no":
        return "NO" if item.answer == "YES" else "YES"
    if item.value_kind == "number":
        try:
            return str(float(item.answer) + 7).removesuffix(".0")
        except ValueError:
            return "7"
    return item.answer + " x"


def number_forms(item: PerceptionItem) -> dict[str, str]:
    """Ways of writing the same number (numbers only)."""
    if item.value_kind != "number" or not item.answer.lstrip("-").isdigit():
        return {}
    return {"decimal point": f"{item.answer}.0", "unicode minus": item.answer.replace("-", "\u2212")}


def tally(rows: list[tuple[str, bool, bool, bool]]) -> list[str]:
    """Table lines: per style, right answers' accuracy under each scoring, wrong answers accepted, disagreement."""
    styles = list(dict.fromkeys(style for style, *_ in rows))
    lines = ["| style | replies | strict acc. | normalized acc. | disagree |", "| --- | --- | --- | --- | --- |"]
    for style in styles:
        mine = [(truth, strict, normalized) for s, truth, strict, normalized in rows if s == style]
        n = len(mine)
        strict_acc = sum(strict == truth for truth, strict, _ in mine) / n
        normalized_acc = sum(normalized == truth for truth, _, normalized in mine) / n
        disagree = sum(strict != normalized for _, strict, normalized in mine)
        lines.append(f"| {style} | {n} | {strict_acc:.1%} | {normalized_acc:.1%} | {disagree} |")
    return lines


def main() -> None:
    upstream = Path(sys.argv[1] if len(sys.argv) > 1 else "../shared/scratchworld-upstream")
    suite = load_perception_suite(upstream)
    items = suite.items
    rows: list[tuple[str, bool, bool, bool]] = []  # style, reply is right, strict says right, normalized says right
    for item in items:
        for right in (True, False):
            answer = item.answer if right else wrong(item)
            forms = {name: style(answer) for name, style in STYLES.items()}
            if right:
                forms |= number_forms(item)
            for name, reply in forms.items():
                score = score_reply(reply, item.answer, item.answer_format, item.value_kind)
                rows.append((f"{name} ({'right' if right else 'wrong'})", right, score.strict, score.normalized))
    print(f"# Strict (upstream) vs normalized (ours) scoring: {len(items)} items of {suite.name}\n")
    print("Accuracy = share of replies the scoring judges as they are (a right reply right, a wrong one wrong).\n")
    print("\n".join(tally(rows)))

    generated: list[tuple[str, bool, bool, bool]] = []
    for item in items:
        if item.upstream is None:
            continue
        task = json.loads((upstream / TASKS_DIR / f"{item.upstream.task_id}.json").read_text())
        text = str(task.get("response_content") or "")
        if not text:
            continue
        score = score_reply(text, item.answer, item.answer_format, item.value_kind)
        generated.append((f"generator reply ({item.kind})", True, score.strict, score.normalized))
    print(f"\n## Upstream's generator replies ({len(generated)}), each ending on its own label\n")
    print("\n".join(tally(generated)))


if __name__ == "__main__":
    main()
