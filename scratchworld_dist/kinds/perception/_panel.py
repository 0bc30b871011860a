"""A perception attempt on the viewer's job page: the question, the answer as given and read, both scores."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from html import escape

from pydantic import BaseModel

from scratchworld_dist.kinds.perception._rows import PerceptionRow
from scratchworld_dist.viewer import AttemptPanel


def _verdict(right: bool) -> str:
    return f'<span class="badge {"passed" if right else "failed"}">{"right" if right else "wrong"}</span>'


def answer_panel(rows: Mapping[str, Sequence[BaseModel]], root: str) -> AttemptPanel | None:
    """The attempt's answer (None for an attempt without a verdict: it has no row)."""
    answer = next((row for row in rows.get("perception", ()) if isinstance(row, PerceptionRow)), None)
    if answer is None:
        return None
    value_kind = f" ({escape(answer.value_kind)})" if answer.value_kind else ""
    read = f"<code>{escape(answer.extracted)}</code>" if answer.extracted is not None else f"nothing ({answer.parse})"
    body = (
        '<table class="kv perception">\n'
        f"<tr><th>item</th><td>{escape(answer.kind)} · {escape(answer.tag)} · {escape(answer.answer_format)}"
        f"{value_kind}</td></tr>\n"
        f"<tr><th>expected</th><td><code>{escape(answer.expected)}</code></td></tr>\n"
        f'<tr><th>reply</th><td><pre class="reply">{escape(answer.reply)}</pre></td></tr>\n'
        f"<tr><th>read as</th><td>{read}</td></tr>\n"
        f"<tr><th>scores</th><td>normalized {_verdict(answer.normalized_correct)} · strict (upstream) "
        f"{_verdict(answer.strict_correct)}</td></tr>\n"
        "</table>\n"
        f'<figure class="screen"><img loading="lazy" src="{escape(root + answer.screenshot)}" '
        'alt="the item\'s screenshot"><figcaption>the screenshot the question is about</figcaption></figure>'
    )
    return AttemptPanel(title="Answer", html=body, instruction=answer.question, shows_project=False)
