"""Rendering a ``RunReport`` as Markdown, a self-contained HTML page (with its plots), or JSON.

The report is a list of blocks (``scratchworld_dist.reports``), so Markdown and HTML always show the same numbers.
"""

from __future__ import annotations

from collections.abc import Sequence

from scratchworld_dist.kinds.tasks.report._stability_section import StabilitySection
from scratchworld_dist.kinds.tasks.report._summary import KEstimate, ReportRow, RunReport
from scratchworld_dist.reports import (
    Block,
    Heading,
    Paragraph,
    Plot,
    ReportFormat,
    Table,
    blocks_html,
    blocks_markdown,
    html_page,
    plots_html,
)
from workers.contract import AgentUnavailableError

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


def render(report: RunReport, fmt: ReportFormat, plots: Sequence[Plot] = ()) -> str:
    """The report as text in ``fmt`` (``md``, ``html`` or ``json``); only HTML shows ``plots``."""
    if fmt == "json":
        return render_json(report)
    if fmt == "html":
        return render_html(report, plots)
    if fmt == "md":
        return render_markdown(report)
    raise ValueError(f"No renderer for format: {fmt}")


def render_json(report: RunReport) -> str:
    """The report's ``model_dump`` as indented JSON (structure documented on ``RunReport``)."""
    return report.model_dump_json(indent=2) + "\n"


def render_markdown(report: RunReport) -> str:
    return blocks_markdown(_blocks(report))


def render_html(report: RunReport, plots: Sequence[Plot] = ()) -> str:
    """One page with inline style and no external resources; every string is escaped; ``plots`` after the tables."""
    body = render_html_body(report)
    return html_page(body + "\n" + plots_html(plots) if plots else body)


def render_html_body(report: RunReport) -> str:
    """The report's headings, paragraphs and tables as HTML elements (a page's body; the viewer's run page)."""
    return blocks_html(_blocks(report))


def _blocks(report: RunReport) -> list[Block]:
    blocks: list[Block] = [Heading(1, "ScratchWorld report")]
    blocks += [Paragraph(f"Warning: {warning}") for warning in report.warnings]
    blocks += _runs(report)
    timed = any(_on_wall_clock(row.agent) for row in report.rows)  # a human baseline: every row's time beside it
    for mode in sorted({row.mode for row in report.rows}):
        rows = [row for row in report.rows if row.mode == mode]
        blocks += [Heading(2, f"Mode: {mode}"), _main_table(rows, report.categories, timed)]
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
        if run.tags:
            blocks.append(Paragraph(f"Tags ({run.run_name}): " + ", ".join(f"{k}={v}" for k, v in run.tags.items())))
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


def _main_table(rows: list[ReportRow], categories: list[str], timed: bool) -> Table:
    header = ["agent/model", *(f"{c.capitalize()} SR" for c in categories), "SR", "PSR", "coverage", "errors"]
    header += ["mean steps", *(["time per task"] if timed else []), "tokens (in+out)", "cost (USD)"]
    header.append("cost per success")
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
        if timed:
            cells.append("-" if row.mean_agent_s is None else f"{row.mean_agent_s:.1f} s")
        cells += [f"{row.input_tokens + row.output_tokens:,}", _usd(row.cost_usd)]
        cells.append("-" if row.cost_per_success is None else _usd(row.cost_per_success))
        if cache:
            cells.append(_cache_hits(row))
        body.append(cells)
    return Table(header, body)


def _on_wall_clock(agent: str) -> bool:
    """Whether ``agent`` acts on the wall clock (a person: ``real_time``); False for one not installed here."""
    from workers.agent_api import agent_class

    try:
        return bool(getattr(agent_class(agent), "real_time", False))
    except AgentUnavailableError:
        return False


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


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{value * 100:.1f}%"


def _rate(passed: int, determinate: int) -> str:
    return "-" if not determinate else f"{_pct(passed / determinate)} ({passed}/{determinate})"


def _usd(value: float) -> str:
    return f"${value:,.2f}" if value >= 1 else f"${value:.4f}"
