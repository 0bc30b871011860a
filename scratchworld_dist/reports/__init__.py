"""Reports over run directories: the main table as Markdown, HTML (with plots) or JSON, the drag and perception
benchmarks' tables, the diagnosis across benchmarks, and paired comparisons."""

from scratchworld_dist.reports._build import build_report, report_of
from scratchworld_dist.reports._compare import (
    Comparison,
    Difference,
    Selector,
    SideInfo,
    TaskOutcome,
    compare_runs,
    parse_selector,
)
from scratchworld_dist.reports._compare_render import render_comparison
from scratchworld_dist.reports._compare_stats import Interval, McNemar, mcnemar_exact, paired_bootstrap
from scratchworld_dist.reports._diagnosis import DiagnosisRow, DiagnosisTable, Gap, PerceptionRate
from scratchworld_dist.reports._diagnosis_cells import MISSING, Rate, optional_rate, pct, rate_cell
from scratchworld_dist.reports._diagnosis_report import DiagnosisReport
from scratchworld_dist.reports._drag_table import (
    build_drag_report,
    drag_table_of,
    is_drag_run,
    render_drag,
    render_drag_markdown,
)
from scratchworld_dist.reports._metrics import (
    MeanInterval,
    mean_interval,
    mean_pass_at_k,
    mean_pass_hat_k,
    pass_at_k,
    pass_hat_k,
    t_quantile_975,
)
from scratchworld_dist.reports._perception_metrics import PerceptionTable, PerceptionTableRow
from scratchworld_dist.reports._perception_table import (
    build_perception_report,
    is_perception_run,
    perception_blocks,
    perception_table_of,
    render_perception,
)
from scratchworld_dist.reports._plots import Plot, plots_html, plots_of, report_plots
from scratchworld_dist.reports._render import (
    FORMATS,
    ReportFormat,
    blocks_html,
    blocks_markdown,
    render,
    render_html,
    render_html_body,
    render_json,
    render_markdown,
)
from scratchworld_dist.reports._report_runs import report_runs
from scratchworld_dist.reports._run_groups import RunGroup
from scratchworld_dist.reports._summary import (
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
from scratchworld_dist.reports._verdict_changes import VerdictChange, verdict_changes

__all__ = [
    "CATEGORIES",
    "DETERMINATE",
    "FORMATS",
    "MISSING",
    "REPORT_VERSION",
    "CategoryStats",
    "Comparison",
    "DiagnosisReport",
    "DiagnosisRow",
    "DiagnosisTable",
    "Difference",
    "ErrorCount",
    "Gap",
    "Interval",
    "KEstimate",
    "McNemar",
    "MeanInterval",
    "PerceptionRate",
    "PerceptionTable",
    "PerceptionTableRow",
    "Plot",
    "Rate",
    "ReportFormat",
    "ReportRow",
    "RunGroup",
    "RunInfo",
    "RunReport",
    "SeedRate",
    "SeedStats",
    "Selector",
    "SideInfo",
    "TaskOutcome",
    "VerdictChange",
    "blocks_html",
    "blocks_markdown",
    "build_drag_report",
    "build_perception_report",
    "build_report",
    "compare_runs",
    "drag_table_of",
    "is_drag_run",
    "is_perception_run",
    "mcnemar_exact",
    "mean_interval",
    "mean_pass_at_k",
    "mean_pass_hat_k",
    "optional_rate",
    "paired_bootstrap",
    "parse_selector",
    "pass_at_k",
    "pass_hat_k",
    "pct",
    "perception_blocks",
    "perception_table_of",
    "plots_html",
    "plots_of",
    "rate_cell",
    "render",
    "render_comparison",
    "render_drag",
    "render_drag_markdown",
    "render_html",
    "render_html_body",
    "render_json",
    "render_markdown",
    "render_perception",
    "report_of",
    "report_plots",
    "report_runs",
    "t_quantile_975",
    "verdict_changes",
]
