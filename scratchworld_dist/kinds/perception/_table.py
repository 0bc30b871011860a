"""The perception benchmark's report: read run directories into a ``PerceptionTable`` and draw it.

Run directories are loaded as for the main report (manifest required, rows of an older suite or harness
set aside, incomparable runs refused unless forced); the ``perception`` table adds each run's answers.
Markdown and HTML come from the same blocks, so they show the same numbers.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.perception._metrics import (
    Accuracy,
    Confusion,
    PerceptionCell,
    PerceptionTable,
    PerceptionTableRow,
    join_runs,
    perception_rows,
)
from scratchworld_dist.kinds.perception._rows import PerceptionRow
from scratchworld_dist.reports import (
    Block,
    Heading,
    LoadedRun,
    Paragraph,
    ReportFormat,
    Table,
    blocks_html,
    blocks_markdown,
    load_runs,
    read_rows,
    render_text,
    row_label,
    stale_warnings,
)
from scratchworld_dist.results import RunStore, read_manifest

_DEFINITIONS = (
    "One run = the effective attempt of one perception job (item, seed, agent, model): its latest attempt with "
    "an answer, else its latest error. An error run (the model call failed for good) has no answer: it is "
    "counted under errors and in coverage = scored / runs, and left out of every accuracy's denominator (never "
    "counted as a wrong answer). Accuracy = right answers / scored runs, two ways: normalized (ours; decides the "
    "job's outcome) reads the final answer out of the reply (after any reasoning, the last 'answer:' or the last "
    "line; quotes and closing punctuation trimmed; numbers compared as numbers, dropdown options without case); "
    "strict (upstream's) needs the whole reply, stripped, to equal the answer (YES/NO in any case). YES share = "
    "scored runs whose expected answer is YES / scored runs: what answering YES to everything scores. Confusion "
    "is over scored yes/no items with YES as the positive class: TP and TN are the scoring's right answers, FP a "
    "NO item answered YES (on connection items: a link seen where there is none), FN a YES item answered NO; a "
    "wrong answer the scoring cannot read as YES or NO (strict: anything but a bare YES or NO) is unreadable, "
    "not forced into a cell. FP rate = FP / NO items scored, unreadable ones included. Parse failures are the "
    "normalized reading's: no_answer (empty reply), unparsed (no answer of the asked form)."
)


def is_perception_run(run_dir: Path) -> bool:
    """Whether a run directory holds perception jobs: perception rows, or a manifest that says so."""
    if RunStore(run_dir).read_table("perception", columns=["job_id"]).num_rows:
        return True
    manifest = read_manifest(run_dir) if run_dir.is_dir() else None
    return manifest is not None and manifest.config.get("benchmark") == "perception"


def build_perception_report(run_dirs: list[Path], *, force: bool = False) -> PerceptionTable:
    """Merge the perception results of ``run_dirs``; raises ``RunDirError`` when they hold no perception job."""
    loaded, warnings = load_runs(run_dirs, force=force)
    return perception_table_of(loaded, warnings)


def perception_table_of(
    loaded: Sequence[LoadedRun], warnings: list[str], rows: Sequence[PerceptionRow] | None = None
) -> PerceptionTable:
    """The perception table of runs already loaded and checked for merging (``warnings``: those of the check;
    ``rows``: their ``perception`` rows, when read already)."""
    warnings = warnings + stale_warnings(loaded)
    jobs = [row for run in loaded for row in run.rows]
    if rows is None:  # not read already (the diagnosis reads each group's rows once, for both)
        rows = [a for run in loaded for a in read_perception_rows(run.path)]
    runs, notes = join_runs(jobs, rows)
    if not runs:
        raise RunDirError(f"{', '.join(str(r.path) for r in loaded)}: no perception job results")
    return PerceptionTable(runs=[r.name for r in loaded], warnings=warnings + notes, rows=perception_rows(runs))


def read_perception_rows(run_dir: Path) -> list[PerceptionRow]:
    """The ``perception`` rows of a run directory (``RunDirError`` for a row that is not one)."""
    return read_rows(run_dir, "perception", PerceptionRow, "a perception answer")


def render_perception(table: PerceptionTable, fmt: ReportFormat) -> str:
    """The perception report as text in ``fmt`` (``md``, ``html`` or ``json``)."""
    return render_text(
        table,
        lambda: blocks_markdown(perception_blocks(table)),
        fmt,
        body=lambda: blocks_html(perception_blocks(table)),
    )


def perception_blocks(table: PerceptionTable) -> list[Block]:
    """The report's headings, paragraphs and tables."""
    blocks: list[Block] = [Heading(1, "ScratchWorld perception report")]
    blocks += [Paragraph(f"Warning: {w}") for w in table.warnings]
    blocks.append(Paragraph("Runs: " + "; ".join(table.runs)))
    kinds = [k for k in _kinds(table) if any((cell := _kind(row, k)) is not None and cell.runs for row in table.rows)]
    header = ["agent/model", "coverage", "normalized", "strict"]
    header += [f"{kind} {scoring}" for kind in kinds for scoring in ("normalized", "strict")]
    header.append("YES share")
    accuracy = [
        [
            _label(row),
            _coverage(row.overall),
            _accuracy(row.overall.normalized),
            _accuracy(row.overall.strict),
            *(v for kind in kinds for v in _both(_kind(row, kind))),
            _pct(row.overall.yes_share),
        ]
        for row in table.rows
    ]
    blocks += [Heading(2, "Accuracy"), Table(header, accuracy)]
    tags = [
        [_label(row), cell.kind or "-", cell.group, _coverage(cell), *_both(cell), _pct(cell.yes_share)]
        for row in table.rows
        for cell in row.tags
    ]
    tag_header = ["agent/model", "kind", "tag", "coverage", "normalized", "strict", "YES share"]
    blocks += [Heading(2, "Accuracy per tag"), Table(tag_header, tags)]
    confusion = [
        [_label(row), cell.group, str(cell.items), scoring, *_confusion(getattr(cell, scoring))]
        for row in table.rows
        for cell in row.confusion
        for scoring in ("normalized", "strict")
    ]
    confusion_header = ["agent/model", "kind", "yes/no items", "scoring", "TP", "FP", "TN", "FN"]
    confusion_header += ["unreadable (YES items)", "unreadable (NO items)", "FP rate"]
    blocks += [Heading(2, "YES/NO confusion (YES = positive)"), Table(confusion_header, confusion)]
    counts = [
        [
            _label(row),
            str(row.overall.runs),
            str(row.overall.error_runs),
            ", ".join(f"{e.name} {e.runs}" for e in row.errors) or "-",
            ", ".join(f"{p.name} {p.runs}" for p in row.parse_failures) or "none",
            f"{row.input_tokens + row.output_tokens:,}",
            f"${row.cost_usd:.4f}",
        ]
        for row in table.rows
    ]
    counts_header = ["agent/model", "runs", "error runs", "errors by class", "parse failures", "tokens", "cost (USD)"]
    blocks += [Heading(2, "Counts"), Table(counts_header, counts), Paragraph(_DEFINITIONS)]
    return blocks


def _kinds(table: PerceptionTable) -> list[str]:
    seen: list[str] = []
    for row in table.rows:
        seen += [cell.group for cell in row.kinds if cell.group not in seen]
    return seen


def _kind(row: PerceptionTableRow, kind: str) -> PerceptionCell | None:
    return next((cell for cell in row.kinds if cell.group == kind), None)


def _label(row: PerceptionTableRow) -> str:
    return row_label(row.agent, row.model)


def _both(cell: PerceptionCell | None) -> list[str]:
    if cell is None or not cell.runs:
        return ["-", "-"]
    return [_accuracy(cell.normalized), _accuracy(cell.strict)]


def _coverage(cell: PerceptionCell) -> str:
    return "-" if not cell.runs else f"{_pct(cell.coverage)} ({cell.scored}/{cell.runs})"


def _accuracy(value: Accuracy) -> str:
    return "-" if not value.scored else f"{_pct(value.rate)} ({value.correct}/{value.scored})"


def _confusion(value: Confusion) -> list[str]:
    counts = (value.true_positives, value.false_positives, value.true_negatives, value.false_negatives)
    unreadable = (value.unreadable_yes, value.unreadable_no)
    return [*(str(n) for n in counts + unreadable), _pct(value.false_positive_rate)]


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{value * 100:.1f}%"
