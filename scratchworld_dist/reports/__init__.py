"""The report core: what any kind's report is built from (reading and merging runs, blocks rendered as Markdown or
HTML, plots, pass@k and intervals, paired statistics, model identity), the report of a set of runs by the kinds
they hold, and the diagnosis across kinds. Each kind's own report is in its folder (the episodes' in
``scratchworld_dist.kinds.tasks.report``); this package imports none of them.

``draw_plots`` imports matplotlib on first use: reading and reporting as text never load it."""

import typing

import workers
from scratchworld_dist.reports._compare_stats import Interval, McNemar, mcnemar_exact, paired_bootstrap
from scratchworld_dist.reports._diagnosis import (
    MISSING,
    DiagnosisModels,
    DiagnosisPart,
    DiagnosisReportCore,
    DiagnosisRowCore,
    DiagnosisTableCore,
    Rate,
    optional_rate,
    pct,
    rate_cell,
)
from scratchworld_dist.reports._diagnosis_report import diagnosis_models, diagnosis_parts, diagnosis_table
from scratchworld_dist.reports._error_digest import ErrorDigest, digest_lines, error_digest, run_error_digest
from scratchworld_dist.reports._kind import KindReport
from scratchworld_dist.reports._metrics import (
    ClassCount,
    MeanInterval,
    class_counts,
    mean_interval,
    mean_pass_at_k,
    mean_pass_hat_k,
    pass_at_k,
    pass_hat_k,
    t_quantile_975,
)
from scratchworld_dist.reports._model_identity import row_label
from scratchworld_dist.reports._plots import Box, Plot, PlotData, Point, Series, plots_html
from scratchworld_dist.reports._render import (
    FORMATS,
    Block,
    Code,
    Heading,
    Linked,
    Paragraph,
    ReportFormat,
    Table,
    blocks_html,
    blocks_markdown,
    html_page,
    markdown_table,
    render_text,
)
from scratchworld_dist.reports._report_runs import report_data, report_runs
from scratchworld_dist.reports._run_groups import RunGroup
from scratchworld_dist.reports._runs import (
    LoadedRun,
    incompatibilities,
    load_run,
    load_runs,
    read_rows,
    stale_warnings,
    tests_of_attempts,
)
from scratchworld_dist.reports._schemas import LaterFields, report_schemas, write_report_schemas

if typing.TYPE_CHECKING:
    from scratchworld_dist.reports._plot_draw import draw_plots

__getattr__ = workers.lazy_exports(__name__, {"._plot_draw": ("draw_plots",)})

__all__ = [
    "FORMATS",
    "MISSING",
    "Block",
    "Box",
    "ClassCount",
    "Code",
    "DiagnosisModels",
    "DiagnosisPart",
    "DiagnosisReportCore",
    "DiagnosisRowCore",
    "DiagnosisTableCore",
    "ErrorDigest",
    "Heading",
    "Interval",
    "KindReport",
    "LaterFields",
    "Linked",
    "LoadedRun",
    "McNemar",
    "MeanInterval",
    "Paragraph",
    "Plot",
    "PlotData",
    "Point",
    "Rate",
    "ReportFormat",
    "RunGroup",
    "Series",
    "Table",
    "blocks_html",
    "blocks_markdown",
    "class_counts",
    "diagnosis_models",
    "diagnosis_parts",
    "diagnosis_table",
    "digest_lines",
    "draw_plots",
    "error_digest",
    "html_page",
    "incompatibilities",
    "load_run",
    "load_runs",
    "markdown_table",
    "mcnemar_exact",
    "mean_interval",
    "mean_pass_at_k",
    "mean_pass_hat_k",
    "optional_rate",
    "paired_bootstrap",
    "pass_at_k",
    "pass_hat_k",
    "pct",
    "plots_html",
    "rate_cell",
    "read_rows",
    "render_text",
    "report_data",
    "report_runs",
    "report_schemas",
    "row_label",
    "run_error_digest",
    "stale_warnings",
    "t_quantile_975",
    "tests_of_attempts",
    "write_report_schemas",
]
