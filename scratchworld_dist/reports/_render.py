"""Rendering a ``RunReport`` as Markdown, a self-contained HTML page, or JSON.

Markdown and HTML are drawn from one list of blocks (headings, paragraphs, tables of text
cells), so the two always show the same numbers; only the markup differs. The perception and
diagnosis reports are drawn from blocks too (``blocks_markdown``, ``blocks_html``).
"""

from __future__ import annotations

import html
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

from pydantic import BaseModel

from scratchworld_dist.reports._plots import Plot, plots_html
from scratchworld_dist.reports._stability_section import StabilitySection
from scratchworld_dist.reports._summary import KEstimate, ReportRow, RunReport

ReportFormat = Literal["md", "html", "json"]
FORMATS: tuple[ReportFormat, ...] = ("md", "html", "json")

_CACHE_NOTE = (
    "Cache hits: model calls answered from the sweep's model cache with the reply the same request (model, "
    "parameters, seed, every message and image) got before; they made no request and cost nothing, so cost "
    "and cost per success count only the calls sent. Their tokens are those of the replies they replay."
)

_DEFINITIONS = (
    "SR = passed / determinate jobs (outcome passed or failed); PSR = mean fraction of tests passed over "
    "determinate jobs. Jobs whose effective outcome is error have no verdict: they are excluded from SR and PSR "
    "(never counted as failures) and show under errors and coverage = determinate / (recorded + missing) jobs. "
    "Each job counts once, at its latest attempt with a verdict. Mean steps is over determinate jobs; tokens and "
    "cost are over every recorded job (errors included, superseded attempts not: the Runs table has the cost of "
    "all attempts)."
)


@dataclass(frozen=True)
class Heading:
    """A heading of ``level`` (1 is the page title)."""

    level: int
    text: str


@dataclass(frozen=True)
class Paragraph:
    text: str


@dataclass(frozen=True)
class Table:
    """A table of text cells (escaped when drawn, in both markups)."""

    header: list[str]
    rows: list[list[str]]


@dataclass(frozen=True)
class Linked:
    """A paragraph that ends in a link: ``text``, then ``label`` pointing at ``href`` (a relative path we made)."""

    text: str
    label: str
    href: str


@dataclass(frozen=True)
class Code:
    """Preformatted text (pseudocode): a fenced block in Markdown, ``<pre>`` in HTML."""

    text: str


Block = Heading | Paragraph | Linked | Code | Table


def render(report: RunReport, fmt: ReportFormat, plots: Sequence[Plot] = ()) -> str:
    """The report as text in ``fmt`` (``md``, ``html`` or ``json``); only HTML shows ``plots``."""
    if fmt == "json":
        return render_json(report)
    if fmt == "html":
        return render_html(report, plots)
    if fmt == "md":
        return render_markdown(report)
    raise ValueError(f"No renderer for format: {fmt}")


def render_text(
    model: BaseModel, markdown: Callable[[], str], fmt: ReportFormat, body: Callable[[], str] | None = None
) -> str:
    """A report in ``fmt``: its Markdown, a page of its HTML ``body`` (default: the Markdown preformatted), or the
    model's JSON."""
    if fmt == "json":
        return model.model_dump_json(indent=2) + "\n"
    if fmt == "html":
        return html_page(body() if body is not None else f"<pre>{html.escape(markdown())}</pre>")
    if fmt == "md":
        return markdown()
    raise ValueError(f"No renderer for format: {fmt}")


def render_json(report: RunReport) -> str:
    """The report's ``model_dump`` as indented JSON (structure documented on ``RunReport``)."""
    return report.model_dump_json(indent=2) + "\n"


def render_markdown(report: RunReport) -> str:
    return blocks_markdown(_blocks(report))


def blocks_markdown(blocks: Sequence[Block]) -> str:
    """Headings, paragraphs and tables as Markdown (a report of its own: the text ends with a newline)."""
    parts = []
    for block in blocks:
        if isinstance(block, Heading):
            parts.append(f"{'#' * block.level} {block.text}")
        elif isinstance(block, Paragraph):
            parts.append(block.text)
        elif isinstance(block, Linked):
            parts.append(f"{block.text} [{block.label}](<{block.href}>)")
        elif isinstance(block, Code):
            fence = "`" * max(3, 1 + max((len(run) for run in re.findall(r"`+", block.text)), default=0))
            parts.append(f"{fence}\n{block.text}\n{fence}")
        else:
            lines = [_md_row(block.header), _md_row(["---"] * len(block.header))]
            lines += [_md_row(row) for row in block.rows]
            parts.append("\n".join(lines))
    return "\n\n".join(parts) + "\n"


def render_html(report: RunReport, plots: Sequence[Plot] = ()) -> str:
    """One page with inline style and no external resources; every string is escaped; ``plots`` after the tables."""
    body = render_html_body(report)
    return html_page(body + "\n" + plots_html(plots) if plots else body)


def render_html_body(report: RunReport) -> str:
    """The report's headings, paragraphs and tables as HTML elements (a page's body; the viewer's run page)."""
    return blocks_html(_blocks(report))


def html_page(body: str) -> str:
    """A self-contained page (inline style, no external resources) around ``body``, which must be escaped HTML."""
    return _PAGE.format(body=body)


def blocks_html(blocks: Sequence[Block]) -> str:
    """Headings, paragraphs and tables as HTML elements, every string escaped."""
    body = []
    for block in blocks:
        if isinstance(block, Heading):
            body.append(f"<h{block.level}>{html.escape(block.text)}</h{block.level}>")
        elif isinstance(block, Paragraph):
            body.append(f"<p>{html.escape(block.text)}</p>")
        elif isinstance(block, Linked):
            link = f'<a href="{html.escape(block.href)}">{html.escape(block.label)}</a>'
            body.append(f"<p>{html.escape(block.text)} {link}</p>")
        elif isinstance(block, Code):
            body.append(f"<pre>{html.escape(block.text)}</pre>")
        else:
            head = "".join(f"<th>{html.escape(cell)}</th>" for cell in block.header)
            rows = "".join(
                "<tr>" + "".join(f"<td>{html.escape(cell)}</td>" for cell in row) + "</tr>" for row in block.rows
            )
            body.append(f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>")
    return "\n".join(body)


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>ScratchWorld report</title>
<style>
body {{ font-family: system-ui, sans-serif; margin: 2em; color: #222; }}
table {{ border-collapse: collapse; margin: 1em 0; }}
th, td {{ border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: right; }}
th:first-child, td:first-child {{ text-align: left; }}
th {{ background: #f3f3f3; }}
</style>
</head>
<body>
{body}
</body>
</html>
"""


def _blocks(report: RunReport) -> list[Block]:
    blocks: list[Block] = [Heading(1, "ScratchWorld report")]
    blocks += [Paragraph(f"Warning: {warning}") for warning in report.warnings]
    blocks += _runs(report)
    for mode in sorted({row.mode for row in report.rows}):
        rows = [row for row in report.rows if row.mode == mode]
        blocks += [Heading(2, f"Mode: {mode}"), _main_table(rows, report.categories)]
        if any(row.seeds is not None for row in rows):
            blocks += [Heading(3, f"Across seeds ({mode})"), _seed_table(rows)]
    if report.stability is not None:
        blocks += _stability(report.stability)
    blocks.append(Paragraph(_DEFINITIONS))
    if any(row.llm_cache_hits is not None for row in report.rows):
        blocks.append(Paragraph(_CACHE_NOTE))
    blocks += _errors(report)
    return blocks


def _runs(report: RunReport) -> list[Block]:
    header = ["run", "path", "suite", "suite hash", "harness", "planned", "recorded", "determinate", "errors"]
    header += ["missing", "stale rows", "attempts", "cost of all attempts"]
    rows = [
        [
            *(r.run_name, r.path, r.suite_name, r.suite_hash, r.harness, str(r.planned_jobs)),
            *(str(n) for n in (r.recorded_jobs, r.determinate, r.errors, r.missing, r.stale_rows, r.attempts)),
            _usd(r.attempts_cost_usd),
        ]
        for r in report.runs
    ]
    blocks: list[Block] = [Heading(2, "Runs"), Table(header, rows)]
    for run in report.runs:
        if run.budget_stop:
            blocks.append(Paragraph(f"Stopped by budget ({run.run_name}): {run.budget_stop}."))
    missing = sum(r.missing for r in report.runs)
    if missing:
        blocks.append(
            Paragraph(
                f"Missing: {missing} planned job(s) have no result (never run, lost, or still running); "
                "they lower coverage and are not counted as failures."
            )
        )
    return blocks


def _main_table(rows: list[ReportRow], categories: list[str]) -> Table:
    header = ["agent/model", *(f"{c.capitalize()} SR" for c in categories), "SR", "PSR", "coverage", "errors"]
    header += ["mean steps", "tokens (in+out)", "cost (USD)", "cost per success"]
    cache = any(row.llm_cache_hits is not None for row in rows)
    if cache:  # only runs that used the model cache show the column
        header.append("cache hits")
    body = []
    for row in rows:
        cells = [row.label]
        for category in categories:
            stats = row.categories.get(category)
            cells.append(_rate(stats.passed, stats.determinate) if stats else "-")
        planned = row.jobs + (row.missing or 0)
        cells += [_rate(row.passed, row.determinate), _pct(row.psr)]
        cells.append(f"{_pct(row.coverage)} ({row.determinate}/{planned})")
        cells += [str(row.errors), "-" if row.mean_steps is None else f"{row.mean_steps:.1f}"]
        cells += [f"{row.input_tokens + row.output_tokens:,}", _usd(row.cost_usd)]
        cells.append("-" if row.cost_per_success is None else _usd(row.cost_per_success))
        if cache:
            cells.append(_cache_hits(row))
        body.append(cells)
    return Table(header, body)


def _seed_table(rows: list[ReportRow]) -> Table:
    most = max(len(row.seeds.pass_at_k) for row in rows if row.seeds is not None)
    header = ["agent/model", "seeds", "SR mean ± 95% CI", *(f"pass@{k}" for k in range(1, most + 1))]
    header += [f"pass^{k}" for k in range(1, most + 1)]
    body = []
    for row in rows:
        if row.seeds is None:
            continue
        sr = row.seeds.sr
        ci = (
            "-" if sr is None else _pct(sr.mean) + ("" if sr.half_width is None else f" ± {sr.half_width * 100:.1f} pp")
        )
        cells = [row.label, ", ".join(str(s.seed) for s in row.seeds.per_seed), ci]
        cells += _estimates(row.seeds.pass_at_k, most) + _estimates(row.seeds.pass_hat_k, most)
        body.append(cells)
    return Table(header, body)


def _stability(stability: StabilitySection) -> list[Block]:
    """One paragraph, and a table of the tasks with unstable tests (each test named once, with its note)."""
    unstable = stability.unstable_tasks
    text = (
        f"Known test stability ({'; '.join(stability.sources)}): {stability.checked} of {stability.tasks} task(s) "
        f"checked; {len(unstable)} task(s) have tests whose verdict can change with frame timing or phase (marked "
        f"unstable). {stability.failed_on_unstable_only} failed job verdict(s) rest on them alone: every test "
        "those jobs failed is unstable, so without those tests they would pass."
    )
    if stability.runs_without:
        text += f" Runs without stability data (their tests are not marked): {', '.join(stability.runs_without)}."
    blocks: list[Block] = [Heading(2, "Unstable tests"), Paragraph(text)]
    if unstable:
        header = ["task", "unstable tests", "jobs with a verdict", "failed", "failed only on unstable tests"]
        rows = [
            [
                task.task_id,
                "; ".join(f"{name!r} ({note})" for name, note in task.tests.items()),
                *(str(n) for n in (task.determinate, task.failed, task.failed_on_unstable_only)),
            ]
            for task in unstable
        ]
        blocks.append(Table(header, rows))
    return blocks


def _errors(report: RunReport) -> list[Block]:
    blocks: list[Block] = [Heading(2, "Errors")]
    if not report.errors:
        return [*blocks, Paragraph("No job ended in error.")]
    rows = [[e.error_class, str(e.jobs), str(e.attempts)] for e in report.errors]
    blocks.append(Table(["error class", "jobs (effective outcome)", "attempts (all)"], rows))
    blocks.append(Paragraph(f"Recovered: {report.recovered_jobs} job(s) had an error attempt and later a verdict."))
    return blocks


def _estimates(estimates: list[KEstimate], width: int) -> list[str]:
    cells = [
        f"{_pct(e.value)} ({e.tasks} task{'s' * (e.tasks != 1)})" if e.value is not None else "-" for e in estimates
    ]
    return cells + ["-"] * (width - len(cells))


def _cache_hits(row: ReportRow) -> str:
    if row.llm_cache_hits is None or row.llm_cache_calls is None:
        return "-"
    if not row.llm_cache_calls:
        return "0/0"
    return f"{row.llm_cache_hits:,}/{row.llm_cache_calls:,} ({_pct(row.llm_cache_hits / row.llm_cache_calls)})"


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A Markdown table; a cell's ``|`` is escaped and its line breaks become spaces."""
    return "\n".join(_md_row(line) for line in [header, ["---"] * len(header), *rows])


def _md_row(cells: Sequence[str]) -> str:
    return "| " + " | ".join(c.replace("|", "\\|").replace("\n", " ") for c in cells) + " |"


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{value * 100:.1f}%"


def _rate(passed: int, determinate: int) -> str:
    return "-" if not determinate else f"{_pct(passed / determinate)} ({passed}/{determinate})"


def _usd(value: float) -> str:
    return f"${value:,.2f}" if value >= 1 else f"${value:.4f}"
