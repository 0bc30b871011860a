"""The report over runs of several benchmarks: the diagnosis table (one row per model, each kind's cells) first,
then each benchmark's own report.

Markdown puts the reports one after the other; HTML makes one page of them (each section as its kind renders it:
the episodes' plots after their tables); JSON is one ``DiagnosisReport`` (``diagnosis_models().report``).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from pydantic import BaseModel, JsonValue

from scratchworld_dist.kinds import job_kind, job_kinds
from scratchworld_dist.reports._diagnosis import (
    MISSING,
    DiagnosisModels,
    DiagnosisPart,
    DiagnosisReportCore,
    DiagnosisRowCore,
    DiagnosisTableCore,
    models_of,
    section_field,
)
from scratchworld_dist.reports._kind import KindReport
from scratchworld_dist.reports._model_identity import ModelKey, ModelResolver, RowModel, describe, row_label
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


def diagnosis_parts() -> list[DiagnosisPart]:
    """The installed kinds' diagnosis parts, in the kinds' order."""
    return [part for kind in job_kinds(KindReport) if (part := kind.diagnosis()) is not None]


def diagnosis_models() -> DiagnosisModels:
    """The diagnosis's row, table and report models for the installed kinds (each kind's fields in them)."""
    return models_of(tuple(diagnosis_parts()))


def diagnosis_report(groups: list[RunGroup], table: DiagnosisTableCore) -> DiagnosisReportCore:
    """The table and each group's section, as its kind makes it."""
    sections = {}
    for group in groups:
        part = job_kind(group.benchmark, KindReport).diagnosis()
        if part is not None:
            sections[section_field(part)] = part.section(group)
    return diagnosis_models().report(diagnosis=table, **sections)


def render_diagnosis_report(report: DiagnosisReportCore, fmt: ReportFormat, groups: list[RunGroup]) -> str:
    """The report as text in ``fmt`` (``md``, ``html`` or ``json``); the sections follow the table in the kinds'
    order, each rendered by its kind (HTML shows the episodes' plots after their tables)."""
    if fmt == "json":
        return report.model_dump_json(indent=2) + "\n"
    if fmt not in ("md", "html"):
        raise ValueError(f"No renderer for format: {fmt}")
    blocks = diagnosis_blocks(report.diagnosis)
    parts = [blocks_markdown(blocks) if fmt == "md" else blocks_html(blocks)]
    for group in groups:
        part = job_kind(group.benchmark, KindReport).diagnosis()
        section = getattr(report, section_field(part), None) if part is not None else None
        if part is not None and section is not None:
            parts.append(part.render_section(section, fmt, group))
    return "\n".join(parts) if fmt == "md" else html_page("\n".join(parts))


def diagnosis_blocks(table: DiagnosisTableCore) -> list[Block]:
    """The diagnosis table's heading, warnings, runs, table and definitions."""
    parts = _parts(table)
    blocks: list[Block] = [Heading(1, "ScratchWorld diagnosis")]
    blocks += [Paragraph(f"Warning: {w}") for w in table.warnings]
    blocks += [Paragraph(f"{_runs_label(b)}: {'; '.join(names)}") for b, names in table.runs.items()]
    header = ["agent/model"] + [cell for part in parts for cell in part.header(table)]
    rows = [[row.label] + [cell for part in parts for cell in part.row(row, table)] for row in table.rows]
    definitions = " ".join([_DEFINITIONS, *(part.definitions for part in diagnosis_parts())])
    return [*blocks, Heading(2, "Diagnosis table"), Table(header, rows), Paragraph(definitions)]


def _parts(table: DiagnosisTableCore) -> list[DiagnosisPart]:
    """The diagnosis parts of the kinds the table has runs of, in the kinds' order."""
    return [p for kind in job_kinds(KindReport) if kind.name in table.runs and (p := kind.diagnosis()) is not None]


def _runs_label(benchmark: str) -> str:
    part = job_kind(benchmark, KindReport).diagnosis()
    return part.runs_label if part is not None else benchmark


@dataclass
class _Results:
    """What the runs hold for one model key, gathered before any metric: per kind, its diagnosis units."""

    labels: list[str] = field(default_factory=list)
    models: list[dict[str, JsonValue]] = field(default_factory=list)
    units: dict[str, list[Any]] = field(default_factory=lambda: defaultdict(list))


def diagnosis_table(groups: Sequence[RunGroup]) -> DiagnosisTableCore:
    """The table over run groups of different benchmarks; each kind's part says what its cells hold."""
    results: dict[ModelKey, _Results] = defaultdict(_Results)
    warnings: list[str] = []
    axes: dict[str, Any] = {}
    for group in groups:
        part = job_kind(group.benchmark, KindReport).diagnosis()
        if part is None:
            continue
        models, unresolved = _models_of(group)
        warnings += unresolved
        units = part.units(group)
        for job_id, unit in units:
            _gathered(results, models[job_id]).units[group.benchmark].append(unit)
        found = part.axes([unit for _, unit in units])
        axes.update(_fields(found) if found is not None else {})
    labels = _labels(results)
    rows = [diagnosis_row(labels[key], key, found) for key, found in results.items()]
    return diagnosis_models().table(
        runs={group.benchmark: [run.name for run in group.runs] for group in groups},
        warnings=warnings,
        rows=sorted(rows, key=lambda r: (r.scripted, r.label)),
        **axes,
    )


def diagnosis_row(label: str, key: ModelKey, found: _Results) -> DiagnosisRowCore:
    """One row: each kind's cells from the units gathered for its key."""
    cells: dict[str, Any] = {}
    for benchmark, units in found.units.items():
        part = job_kind(benchmark, KindReport).diagnosis()
        if part is not None:
            cells.update(_fields(part.cells(units)))
    return diagnosis_models().row(
        label=label, agent=key.agent, scripted=key.scripted, labels=found.labels, models=found.models, **cells
    )


def _fields(model: BaseModel) -> dict[str, Any]:
    """A part's cells or axes as the row's or table's fields (their values as they are, models included)."""
    return {name: getattr(model, name) for name in type(model).model_fields}


def _gathered(results: dict[ModelKey, _Results], resolved: RowModel) -> _Results:
    """The results of ``resolved``'s key, noting the label it went by here."""
    found = results[resolved.key]
    if resolved.label not in found.labels:
        found.labels.append(resolved.label)
    if not found.models:
        found.models = [identity for _, identity in resolved.components]
    return found


def _models_of(group: RunGroup) -> tuple[dict[str, RowModel], list[str]]:
    """Each job's resolved model, by job id, and a warning per run for labels its manifest does not describe."""
    models: dict[str, RowModel] = {}
    warnings = []
    for run in group.runs:
        resolver = ModelResolver(run.manifest, str(run.path / "manifest.json"))
        for row in run.rows:
            models.setdefault(row.job_id, resolver.resolve(row.agent, row.model))
        if resolver.unresolved:
            names = ", ".join(sorted(resolver.unresolved))
            warnings.append(f"{run.name}: model(s) {names} not in the manifest's models: matched by label only")
    return models, warnings


def _labels(results: dict[ModelKey, _Results]) -> dict[ModelKey, str]:
    """Row labels: the first model label seen (scripted agents: their name); rows that would share one
    show what differs between their models, and other names a model went by are listed."""
    base = {
        key: f"{key.agent} [scripted]" if key.scripted else row_label(key.agent, found.labels[0])
        for key, found in results.items()
    }
    clashes: dict[str, list[ModelKey]] = defaultdict(list)
    for key, label in base.items():
        clashes[label].append(key)
    labels = dict(base)
    for label, keys in clashes.items():
        if len(keys) < 2:
            continue
        items = {key: _items(results[key]) for key in keys}
        common = set.intersection(*(set(v) for v in items.values()))
        for number, key in enumerate(keys, start=1):
            differing = [item for item in items[key] if item not in common] or [f"#{number}"]
            labels[key] = f"{label} ({', '.join(differing)})"
    for key, found in results.items():
        if len(found.labels) > 1:
            labels[key] += f" (also named {', '.join(found.labels[1:])})"
    return labels


def _items(found: _Results) -> list[str]:
    """A model's identity as ``name=value`` items; the extra models of a ``+`` label prefixed by their name."""
    names = found.labels[0].split("+") if len(found.models) > 1 else [found.labels[0]]
    items = []
    for index, identity in enumerate(found.models):
        prefix = f"{names[index]}: " if index and index < len(names) else ""
        items += [prefix + item for item in describe(identity)]
    return items
