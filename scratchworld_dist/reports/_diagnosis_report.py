"""The report over runs of several benchmarks: the diagnosis table first, then each benchmark's own report.

Markdown puts the reports one after the other; HTML makes one page of them (the episodes' plots after
their tables); JSON is one ``DiagnosisReport``.
"""

from __future__ import annotations

import html
from collections.abc import Sequence

from pydantic import BaseModel

from scratchworld_dist.reports._diagnosis import (
    START_END_SETTING,
    DiagnosisRow,
    DiagnosisTable,
    Gap,
    PerceptionRate,
    Rate,
)
from scratchworld_dist.reports._drag_metrics import DragTable
from scratchworld_dist.reports._drag_table import render_drag_markdown
from scratchworld_dist.reports._perception_metrics import ALL, PerceptionTable
from scratchworld_dist.reports._perception_table import perception_blocks
from scratchworld_dist.reports._plots import Plot, plots_html
from scratchworld_dist.reports._render import (
    Block,
    Heading,
    Paragraph,
    ReportFormat,
    Table,
    blocks_html,
    blocks_markdown,
    html_page,
    render_html_body,
    render_markdown,
)
from scratchworld_dist.reports._summary import RunReport

_RUNS = {"tasks": "Episode runs", "drag": "Drag runs", "perception": "Perception runs"}

MISSING = "\u2013"
"""An en dash: the model has no result there (never shown as 0)."""

_DEFINITIONS = (
    "One row per model: the LiteLLM model with its temperature, max_tokens and params, matched across runs by "
    "that identity, not by its label (one model named differently is one row; one name with other parameters "
    "is two, labelled by what differs). Where it is served, its key and rate limits and its coordinate "
    "convention do not make another model. The same model driven by another agent is another row; scripted "
    f"agents are rows of their own, by agent name. {MISSING} = no result for that model there, never 0. Every "
    "rate is over runs with a verdict (each job's effective attempt; error runs are left out and counted in "
    "each benchmark's own report), n = those runs. Composite and primitive SR = passed / decided episode jobs. "
    "Gap = composite SR - primitive SR in percentage points: with two or more seeds decided in both modes, the "
    "mean of the per-seed gaps ± the half-width of its 95% t interval; with fewer, the difference of the "
    "pooled SRs, without an interval. Drag Pass@1 = mean over tasks of passes / runs (the unbiased estimator at "
    f"k = 1), per setting; start and end accuracy are of the {START_END_SETTING} setting, the unaided one: "
    "start = runs pressing inside the start region / runs, end = connected / good starts (n = good starts). "
    "Perception = accuracy per item kind and overall as normalized / strict (our reading of the answer / "
    "upstream's exact match), over the scored runs."
)


class DiagnosisReport(BaseModel):
    """The diagnosis table and the report of each benchmark given (None: no run of it)."""

    version: int = 1
    diagnosis: DiagnosisTable
    episodes: RunReport | None = None
    drag: DragTable | None = None
    perception: PerceptionTable | None = None

    @property
    def warnings(self) -> list[str]:
        """The table's and every section's."""
        sections = [s.warnings for s in (self.episodes, self.drag, self.perception) if s is not None]
        return self.diagnosis.warnings + [w for warnings in sections for w in warnings]


def render_diagnosis_report(report: DiagnosisReport, fmt: ReportFormat, plots: Sequence[Plot] = ()) -> str:
    """The report as text in ``fmt`` (``md``, ``html`` or ``json``); only HTML shows the episodes' ``plots``."""
    if fmt == "json":
        return report.model_dump_json(indent=2) + "\n"
    if fmt == "md":
        parts = [blocks_markdown(diagnosis_blocks(report.diagnosis))]
        if report.episodes is not None:
            parts.append(render_markdown(report.episodes))
        if report.drag is not None:
            parts.append(render_drag_markdown(report.drag))
        if report.perception is not None:
            parts.append(blocks_markdown(perception_blocks(report.perception)))
        return "\n".join(parts)
    if fmt == "html":
        body = [blocks_html(diagnosis_blocks(report.diagnosis))]
        if report.episodes is not None:
            body.append(render_html_body(report.episodes))
            if plots:
                body.append(plots_html(plots))
        if report.drag is not None:
            body.append(f"<pre>{html.escape(render_drag_markdown(report.drag))}</pre>")
        if report.perception is not None:
            body.append(blocks_html(perception_blocks(report.perception)))
        return html_page("\n".join(body))
    raise ValueError(f"No renderer for format: {fmt}")


def diagnosis_blocks(table: DiagnosisTable) -> list[Block]:
    """The diagnosis table's heading, warnings, runs, table and definitions."""
    blocks: list[Block] = [Heading(1, "ScratchWorld diagnosis")]
    blocks += [Paragraph(f"Warning: {w}") for w in table.warnings]
    blocks += [Paragraph(f"{_RUNS.get(b, b)}: {'; '.join(names)}") for b, names in table.runs.items()]
    header = ["agent/model"]
    if "tasks" in table.runs:
        header += ["composite SR", "primitive SR", "gap (pp, 95% CI)"]
    if "drag" in table.runs:
        header += [f"drag Pass@1 {setting}" for setting in table.drag_settings]
        header += [f"drag start acc. ({START_END_SETTING})", f"drag end acc. ({START_END_SETTING})"]
    if "perception" in table.runs:
        header += [f"perception {kind} (norm. / strict)" for kind in table.perception_kinds]
        header.append("perception overall (norm. / strict)")
    rows = [_cells(row, table) for row in table.rows]
    return [*blocks, Heading(2, "Diagnosis table"), Table(header, rows), Paragraph(_DEFINITIONS)]


def _cells(row: DiagnosisRow, table: DiagnosisTable) -> list[str]:
    cells = [row.label]
    if "tasks" in table.runs:
        cells += [_rate(row.composite_sr), _rate(row.primitive_sr), _gap(row.gap)]
    if "drag" in table.runs:
        cells += [_rate(row.drag_pass_at_1.get(setting)) for setting in table.drag_settings]
        cells += [_rate(row.drag_start_accuracy), _rate(row.drag_end_accuracy)]
    if "perception" in table.runs:
        cells += [_perception(row.perception.get(kind)) for kind in [*table.perception_kinds, ALL]]
    return cells


def _rate(rate: Rate | None) -> str:
    return MISSING if rate is None else f"{_pct(rate.value)} (n={rate.n})"


def _gap(gap: Gap | None) -> str:
    if gap is None:
        return MISSING
    text = f"{gap.points:+.1f}"
    if gap.half_width is not None:
        return f"{text} ± {gap.half_width:.1f} ({gap.seeds} seeds)"
    return f"{text} ({gap.seeds} seed{'s' * (gap.seeds != 1)}, no CI)"


def _perception(rate: PerceptionRate | None) -> str:
    return MISSING if rate is None else f"{_pct(rate.normalized)} / {_pct(rate.strict)} (n={rate.n})"


def _pct(value: float) -> str:
    return f"{value * 100:.1f}%"
