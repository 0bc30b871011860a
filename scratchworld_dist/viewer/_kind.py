"""What the viewer asks of a benchmark kind: the body of one run's page, and its part of a job's page."""

from __future__ import annotations

import html
from collections.abc import Mapping, Sequence
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.kinds import KindTraits


class AttemptPanel(BaseModel):
    """A kind's part of one attempt on the viewer's job page, above its tests."""

    title: str
    html: str
    """The panel's body: an HTML fragment, every value in it escaped by the kind."""

    instruction: str | None = None
    """What the page shows as the job's instruction instead of the task's (a perception item's question)."""

    shows_project: bool = True
    """Whether the attempt's final project belongs on the page (False when its jobs edit no project)."""


class KindPanel(KindTraits):
    """The viewer facet of a kind. Defaults: no panel of its own (the page's tests, steps and final project)."""

    def report_html(self, run_dir: Path) -> tuple[str, list[str]]:
        """The body of one run's page in the viewer (HTML, escaped), and its warnings."""
        return f"<p>{html.escape(self.title)}: no report of its own.</p>", []

    def attempt_panel(self, rows: Mapping[str, Sequence[BaseModel]], root: str, run_dir: Path) -> AttemptPanel | None:
        """What the job page shows of one attempt's rows in this kind's ``tables`` (None: nothing); ``root`` is
        the run directory as the page links to it (``../``), ``run_dir`` where it is on disk (for what the rows
        only refer to: the audit reads its run's manifest to show the programs a row names)."""
        return None
