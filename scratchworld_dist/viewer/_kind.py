"""What the viewer asks of a benchmark kind: the body of one run's page and its plots, its part of a job's page, and
the comparison pages it offers (between two of its runs, and within one run)."""

from __future__ import annotations

import html
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

from pydantic import BaseModel

from scratchworld_dist.kinds import KindTraits
from scratchworld_dist.results import JobRow


class AttemptPanel(BaseModel):
    """A kind's part of one attempt on the viewer's job page, above its tests."""

    title: str
    html: str
    """The panel's body: an HTML fragment, every value in it escaped by the kind."""

    instruction: str | None = None
    """What the page shows as the job's instruction instead of the task's (a perception item's question)."""

    shows_project: bool = True
    """Whether the attempt's final project belongs on the page (False when its jobs edit no project)."""


@dataclass(frozen=True)
class RunComparison:
    """A page comparing one run with itself (``compare/<k>-<name>.html``): the episodes' composite against their
    primitive jobs."""

    name: str
    """Its part of the page's path: lower-case letters and ``_``."""

    title: str
    """What it compares (``composite vs primitive``): the page is titled by the run's folder and this."""

    note: str = ""
    """Said after the title where the runs page lists it (``reasoning-acting gap``)."""


class KindPanel(KindTraits):
    """The viewer facet of a kind. Defaults: no panel of its own (the page's tests, steps and final project), no
    plots and no comparison pages."""

    compares_runs: ClassVar[bool] = False
    """Whether the runs page offers a comparison of two of its runs (``comparison_html``)."""

    def report_html(self, run_dir: Path) -> tuple[str, list[str]]:
        """The body of one run's page in the viewer (HTML, escaped), and its warnings."""
        return f"<p>{html.escape(self.title)}: no report of its own.</p>", []

    def plots_html(self, rows: Sequence[JobRow]) -> str:
        """The plots of one run's page, from the attempt rows the page read ("" for none): an HTML fragment,
        escaped. The viewer draws them again only when the run's results change."""
        return ""

    def attempt_panel(self, rows: Mapping[str, Sequence[BaseModel]], root: str, run_dir: Path) -> AttemptPanel | None:
        """What the job page shows of one attempt's rows in this kind's ``tables`` (None: nothing); ``root`` is
        the run directory as the page links to it (``../``), ``run_dir`` where it is on disk (for what the rows
        only refer to: the audit reads its run's manifest to show the programs a row names)."""
        return None

    def comparison_html(self, a: Path, b: Path) -> str:
        """Run ``a`` against run ``b`` (both of this kind), as an HTML fragment, escaped; ``RunDirError`` when they
        cannot be compared (the page says why)."""
        raise NotImplementedError(f"benchmark {self.name} compares no runs")

    def run_comparisons(self, rows: Sequence[JobRow]) -> list[RunComparison]:
        """The comparisons within one run the runs page lists, from its effective rows."""
        return []

    def run_comparison_html(self, run_dir: Path, name: str) -> str:
        """The comparison ``name`` (one ``run_comparisons`` listed) within the run at ``run_dir``, as
        ``comparison_html`` makes one."""
        raise NotImplementedError(f"benchmark {self.name} has no comparison {name!r}")
