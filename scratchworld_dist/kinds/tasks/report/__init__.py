"""The task-episode report: SR/PSR per category and mode over merged runs (``RunReport``: Markdown, HTML with its
plots, JSON), the episode plots, known test stability, and paired comparisons of systems (``compare``, the
ranking of several, ``--stable-only``, a regrade against its source), for the CLI and the viewer's pages. Built
from the report core (``scratchworld_dist.reports``)."""

from scratchworld_dist.kinds.tasks.report._build import build_report, report_of
from scratchworld_dist.kinds.tasks.report._compare import (
    Comparison,
    Difference,
    RegradeNote,
    Selector,
    SideInfo,
    TaskOutcome,
    compare_runs,
    parse_selector,
)
from scratchworld_dist.kinds.tasks.report._compare_render import comparison_html, render_comparison
from scratchworld_dist.kinds.tasks.report._plots import plots_of, report_plots
from scratchworld_dist.kinds.tasks.report._ranking import (
    PairTest,
    RankedSystem,
    Ranking,
    holm,
    rank_systems,
    render_ranking,
)
from scratchworld_dist.kinds.tasks.report._render import (
    render,
    render_html,
    render_html_body,
    render_json,
    render_markdown,
)
from scratchworld_dist.kinds.tasks.report._stability_section import StabilitySection, UnstableTask
from scratchworld_dist.kinds.tasks.report._stable_only import NO_STABLE_TEST, StableOnly, StableSide
from scratchworld_dist.kinds.tasks.report._summary import (
    CATEGORIES,
    DETERMINATE,
    REPORT_VERSION,
    CategoryStats,
    ErrorCount,
    KEstimate,
    ReportRow,
    RunInfo,
    RunReport,
    SeedRate,
    SeedStats,
)
from scratchworld_dist.kinds.tasks.report._verdict_changes import VerdictChange, verdict_changes

__all__ = [
    "CATEGORIES",
    "DETERMINATE",
    "NO_STABLE_TEST",
    "REPORT_VERSION",
    "CategoryStats",
    "Comparison",
    "Difference",
    "ErrorCount",
    "KEstimate",
    "PairTest",
    "RankedSystem",
    "Ranking",
    "RegradeNote",
    "ReportRow",
    "RunInfo",
    "RunReport",
    "SeedRate",
    "SeedStats",
    "Selector",
    "SideInfo",
    "StabilitySection",
    "StableOnly",
    "StableSide",
    "TaskOutcome",
    "UnstableTask",
    "VerdictChange",
    "build_report",
    "compare_runs",
    "comparison_html",
    "holm",
    "parse_selector",
    "plots_of",
    "rank_systems",
    "render",
    "render_comparison",
    "render_html",
    "render_html_body",
    "render_json",
    "render_markdown",
    "render_ranking",
    "report_of",
    "report_plots",
    "verdict_changes",
]
