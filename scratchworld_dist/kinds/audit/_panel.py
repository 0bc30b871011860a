"""An audit job on the viewer's job page: the change (pseudocode before and after) and the grader's verdict."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from html import escape

from pydantic import BaseModel

from scratchworld_dist.kinds._protocol import AttemptPanel
from scratchworld_dist.kinds.audit._rows import AuditRow

GOOD = {"killed", "passed", "golden_passes"}


def variant_panel(rows: Mapping[str, Sequence[BaseModel]], root: str) -> AttemptPanel | None:
    row = next((r for r in rows.get("audits", ()) if isinstance(r, AuditRow)), None)
    if row is None:
        return None
    badge = "passed" if row.verdict in GOOD else "failed"
    failing = ", ".join(escape(name) for name in json.loads(row.failing_tests)) or "none"
    body = (
        '<table class="kv audit">\n'
        f"<tr><th>{escape(row.variant)}</th><td>{escape(row.operator)} at {escape(row.target)} / "
        f"{escape(row.block_id)}: {escape(row.description)}</td></tr>\n"
        f'<tr><th>verdict</th><td><span class="badge {badge}">{escape(row.verdict)}</span> '
        f"({row.tests_passed} of {row.tests_total} tests passed; failing: {failing})</td></tr>\n"
        f'<tr><th>before</th><td><pre class="listing">{escape(row.before)}</pre></td></tr>\n'
        f'<tr><th>after</th><td><pre class="listing">{escape(row.after)}</pre></td></tr>\n'
        "</table>"
    )
    return AttemptPanel(title="Variant", html=body, shows_project=False)
