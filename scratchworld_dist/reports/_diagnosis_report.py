"""The report over runs of several benchmarks: the diagnosis table first, then each benchmark's own report.

Markdown puts the reports one after the other; HTML makes one page of them (the episodes' plots after
their tables); JSON is one ``DiagnosisReport``.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, SerializeAsAny

from scratchworld_dist.kinds import DiagnosisPart, job_kind, job_kinds
from scratchworld_dist.reports._diagnosis import DiagnosisTable
from scratchworld_dist.reports._diagnosis_cells import MISSING
from scratchworld_dist.reports._render import (
    Block,
    Heading,
    Paragraph,
    ReportFormat,
    Table,
    blocks_html,
    blocks_markdown,
    html_page,
)
from scratchworld_dist.reports._run_groups import RunGroup
from scratchworld_dist.reports._summary import RunReport

_DEFINITIONS = (
    "One row per model: the LiteLLM model with its temperature, max_tokens and params, matched across runs by "
    "that identity, not by its label (one model named differently is one row; one name with other parameters "
    "is two, labelled by what differs). Where it is served, its key and rate limits and its coordinate "
    "convention do not make another model. The same model driven by another agent is another row; scripted "
    f"agents are rows of their own, by agent name. {MISSING} = no result for that model there, never 0. Every "
    "rate is over runs with a verdict (each job's effective attempt; error runs are left out and counted in "
    "each benchmark's own report), n = those runs."
)
"""What every row means; each kind's part adds what its cells mean."""


class DiagnosisReport(BaseModel):
    """The diagnosis table and the report of each benchmark given (None: no run of it). The built-in kinds'
    sections are the fields below; a plugin kind's is an extra field named by its part's ``section_field``."""

    model_config = ConfigDict(extra="allow")

    version: int = 1
    diagnosis: DiagnosisTable
    episodes: RunReport | None = None
    drag: SerializeAsAny[BaseModel] | None = None
    """The drag kind's table (``kinds.drag.DragTable``)."""

    perception: SerializeAsAny[BaseModel] | None = None
    """The perception kind's table (``kinds.perception.PerceptionTable``)."""

    @property
    def warnings(self) -> list[str]:
        """The table's and every section's."""
        sections = [getattr(self, name) for name in self.model_fields_set if name not in ("version", "diagnosis")]
        return self.diagnosis.warnings + [w for s in sections if s is not None for w in getattr(s, "warnings", [])]


def diagnosis_report(groups: list[RunGroup], table: DiagnosisTable) -> DiagnosisReport:
    """The table and each group's section, as its kind makes it."""
    sections = {}
    for group in groups:
        part = job_kind(group.benchmark).diagnosis()
        if part is not None:
            sections[part.section_field] = part.section(group)
    return DiagnosisReport(diagnosis=table, **sections)


def render_diagnosis_report(report: DiagnosisReport, fmt: ReportFormat, groups: list[RunGroup]) -> str:
    """The report as text in ``fmt`` (``md``, ``html`` or ``json``); the sections follow the table in the kinds'
    order, each rendered by its kind (HTML shows the episodes' plots after their tables)."""
    if fmt == "json":
        return report.model_dump_json(indent=2) + "\n"
    if fmt not in ("md", "html"):
        raise ValueError(f"No renderer for format: {fmt}")
    blocks = diagnosis_blocks(report.diagnosis)
    parts = [blocks_markdown(blocks) if fmt == "md" else blocks_html(blocks)]
    for group in groups:
        part = job_kind(group.benchmark).diagnosis()
        section = getattr(report, part.section_field, None) if part is not None else None
        if part is not None and section is not None:
            parts.append(part.render_section(section, fmt, group))
    return "\n".join(parts) if fmt == "md" else html_page("\n".join(parts))


def diagnosis_blocks(table: DiagnosisTable) -> list[Block]:
    """The diagnosis table's heading, warnings, runs, table and definitions."""
    parts = _parts(table)
    blocks: list[Block] = [Heading(1, "ScratchWorld diagnosis")]
    blocks += [Paragraph(f"Warning: {w}") for w in table.warnings]
    blocks += [Paragraph(f"{_runs_label(b)}: {'; '.join(names)}") for b, names in table.runs.items()]
    header = ["agent/model"] + [cell for part in parts for cell in part.header(table)]
    rows = [[row.label] + [cell for part in parts for cell in part.row(row, table)] for row in table.rows]
    definitions = " ".join([_DEFINITIONS, *(part.definitions for part in _all_parts())])
    return [*blocks, Heading(2, "Diagnosis table"), Table(header, rows), Paragraph(definitions)]


def _parts(table: DiagnosisTable) -> list[DiagnosisPart]:
    """The diagnosis parts of the kinds the table has runs of, in the kinds' order."""
    return [p for kind in job_kinds() if kind.name in table.runs and (p := kind.diagnosis()) is not None]


def _all_parts() -> list[DiagnosisPart]:
    return [p for kind in job_kinds() if (p := kind.diagnosis()) is not None]


def _runs_label(benchmark: str) -> str:
    part = job_kind(benchmark).diagnosis()
    return part.runs_label if part is not None else benchmark
