"""The diagnosis table: one row per model across benchmarks, where its composite episodes fail and why.

Composite and primitive SR come from episode runs, the gap between them is what GUI control costs, and
the diagnostic benchmarks say where that cost arises: the drag benchmark (can the model place one drag)
and the perception benchmark (can it read the workspace). Rows are matched by model identity
(``_model_identity``), never by label; a model without results in a benchmark has no value there (shown
as a dash, never as 0). Every rate is over runs with a verdict: error runs are left out, as in each
benchmark's own report, which has their counts.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from pydantic import BaseModel, ConfigDict, JsonValue

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.reports._diagnosis_cells import Rate
from scratchworld_dist.reports._model_identity import ModelKey, ModelResolver, RowModel, describe
from scratchworld_dist.reports._run_groups import RunGroup
from scratchworld_dist.reports._summary import row_label


class Gap(BaseModel):
    """Composite SR minus primitive SR, in percentage points."""

    points: float
    half_width: float | None
    """Of the 95% t interval over per-seed gaps, in points; None with fewer than two seeds."""

    seeds: int
    """Seeds with verdicts in both modes. With two or more, ``points`` is the mean of the per-seed gaps;
    else it is the difference of the pooled SRs."""


class PerceptionRate(BaseModel):
    """Perception accuracy both ways over the same scored runs."""

    normalized: float
    strict: float
    n: int


class DiagnosisRow(BaseModel):
    """One model (or scripted agent) across the benchmarks given; a missing value means no results there.

    Each kind's diagnosis part fills its own cells (``JobKind.diagnosis``): the built-in kinds' are the
    fields below; a plugin kind's are extra fields of the row."""

    model_config = ConfigDict(extra="allow")

    label: str
    agent: str
    scripted: bool
    labels: list[str]
    """Every model label the runs gave it (several when runs named one model differently)."""

    models: list[dict[str, JsonValue]]
    """The identity of each of its models (empty for a scripted agent)."""

    composite_sr: Rate | None = None
    primitive_sr: Rate | None = None
    gap: Gap | None = None
    drag_pass_at_1: dict[str, Rate] = {}
    """Per drag setting: the unbiased Pass@1 (mean over tasks of passes / runs)."""

    drag_start_accuracy: Rate | None = None
    """In the drag part's start-and-end setting: runs pressing inside the start region / runs."""

    drag_end_accuracy: Rate | None = None
    """In that setting: connected / good starts."""

    perception: dict[str, PerceptionRate] = {}
    """Per item kind, and ``ALL``."""


class DiagnosisTable(BaseModel):
    """The diagnosis over runs of several benchmarks."""

    model_config = ConfigDict(extra="allow")

    version: int = 1
    runs: dict[str, list[str]]
    """Per benchmark (tasks, drag, perception), the run directories read, as ``name (path)``."""

    drag_settings: list[str] = []
    perception_kinds: list[str] = []
    warnings: list[str]
    rows: list[DiagnosisRow]


@dataclass
class _Results:
    """What the runs hold for one model key, gathered before any metric: per kind, its diagnosis units."""

    labels: list[str] = field(default_factory=list)
    models: list[dict[str, JsonValue]] = field(default_factory=list)
    units: dict[str, list[Any]] = field(default_factory=lambda: defaultdict(list))


def diagnosis_table(groups: Sequence[RunGroup]) -> DiagnosisTable:
    """The table over run groups of different benchmarks; each kind's part says what its cells hold."""
    results: dict[ModelKey, _Results] = defaultdict(_Results)
    warnings: list[str] = []
    axes: dict[str, list[str]] = {}
    for group in groups:
        part = job_kind(group.benchmark).diagnosis()
        if part is None:
            continue
        models, unresolved = _models_of(group)
        warnings += unresolved
        units = part.units(group)
        for job_id, unit in units:
            _gathered(results, models[job_id]).units[group.benchmark].append(unit)
        axes.update(part.axes([unit for _, unit in units]))
    labels = _labels(results)
    rows = [diagnosis_row(labels[key], key, found) for key, found in results.items()]
    return DiagnosisTable(
        runs={group.benchmark: [run.name for run in group.runs] for group in groups},
        warnings=warnings,
        rows=sorted(rows, key=lambda r: (r.scripted, r.label)),
        **axes,
    )


def diagnosis_row(label: str, key: ModelKey, found: _Results) -> DiagnosisRow:
    """One row: each kind's cells from the units gathered for its key."""
    cells: dict[str, Any] = {}
    for benchmark, units in found.units.items():
        part = job_kind(benchmark).diagnosis()
        if part is not None:
            cells.update(part.cells(units))
    return DiagnosisRow(
        label=label, agent=key.agent, scripted=key.scripted, labels=found.labels, models=found.models, **cells
    )


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
