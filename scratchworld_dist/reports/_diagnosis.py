"""The diagnosis table: one row per model across benchmarks, where its composite episodes fail and why.

Composite and primitive SR come from episode runs, the gap between them is what GUI control costs, and
the diagnostic benchmarks say where that cost arises: the drag benchmark (can the model place one drag)
and the perception benchmark (can it read the workspace). Rows are matched by model identity
(``_model_identity``), never by label; a model without results in a benchmark has no value there (shown
as a dash, never as 0). Every rate is over runs with a verdict: error runs are left out, as in each
benchmark's own report, which has their counts.
"""

from __future__ import annotations

import statistics
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field

from pydantic import BaseModel, JsonValue

from scratchworld_dist.reports import _drag_metrics as drag
from scratchworld_dist.reports import _perception_metrics as perception
from scratchworld_dist.reports._metrics import mean_interval
from scratchworld_dist.reports._model_identity import ModelKey, ModelResolver, RowModel, describe
from scratchworld_dist.reports._run_groups import RunGroup
from scratchworld_dist.reports._summary import DETERMINATE, row_label
from scratchworld_dist.results import JobRow, effective_rows
from workers.contract import PERCEPTION_KINDS

START_END_SETTING = "baseline"
"""The drag setting whose start and end accuracy the table shows: the unaided one, as the agent acts."""


class Rate(BaseModel):
    """A share and how many runs it is over."""

    value: float
    n: int


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
    """One model (or scripted agent) across the benchmarks given; a missing value means no results there."""

    label: str
    agent: str
    scripted: bool
    labels: list[str]
    """Every model label the runs gave it (several when runs named one model differently)."""

    models: list[dict[str, JsonValue]]
    """The identity of each of its models (empty for a scripted agent)."""

    composite_sr: Rate | None
    primitive_sr: Rate | None
    gap: Gap | None
    drag_pass_at_1: dict[str, Rate]
    """Per drag setting: the unbiased Pass@1 (mean over tasks of passes / runs)."""

    drag_start_accuracy: Rate | None
    """In the ``START_END_SETTING``: runs pressing inside the start region / runs."""

    drag_end_accuracy: Rate | None
    """In the ``START_END_SETTING``: connected / good starts."""

    perception: dict[str, PerceptionRate]
    """Per item kind, and ``ALL``."""


class DiagnosisTable(BaseModel):
    """The diagnosis over runs of several benchmarks."""

    version: int = 1
    runs: dict[str, list[str]]
    """Per benchmark (tasks, drag, perception), the run directories read, as ``name (path)``."""

    drag_settings: list[str]
    perception_kinds: list[str]
    warnings: list[str]
    rows: list[DiagnosisRow]


@dataclass
class _Results:
    """What the runs hold for one model key, gathered before any metric."""

    labels: list[str] = field(default_factory=list)
    models: list[dict[str, JsonValue]] = field(default_factory=list)
    episodes: list[JobRow] = field(default_factory=list)
    drags: list[drag.DragRun] = field(default_factory=list)
    answers: list[perception.PerceptionRun] = field(default_factory=list)


def diagnosis_table(groups: Sequence[RunGroup]) -> DiagnosisTable:
    """The table over run groups of different benchmarks."""
    results: dict[ModelKey, _Results] = defaultdict(_Results)
    warnings: list[str] = []
    settings: set[str] = set()
    kinds: set[str] = set()
    for group in groups:
        models, unresolved = _models_of(group)
        warnings += unresolved
        jobs = [row for run in group.runs for row in run.rows]
        if group.benchmark == "tasks":
            for row in effective_rows(jobs):
                _gathered(results, models[row.job_id]).episodes.append(row)
        elif group.benchmark == "drag":
            drag_runs, _ = drag.join_runs(jobs, group.tables["drags"])  # type: ignore[arg-type]
            for run in drag_runs:
                _gathered(results, models[run.job.job_id]).drags.append(run)
                settings.add(run.job.setting or "")
        else:
            perception_runs, _ = perception.join_runs(jobs, group.tables["perception"])  # type: ignore[arg-type]
            for answered in perception_runs:
                _gathered(results, models[answered.job.job_id]).answers.append(answered)
                kinds.add(answered.kind)
    labels = _labels(results)
    rows = [diagnosis_row(labels[key], key, found) for key, found in results.items()]
    order = {s: i for i, s in enumerate(drag.SETTINGS)}
    kind_order = {k: i for i, k in enumerate(PERCEPTION_KINDS)}
    return DiagnosisTable(
        runs={group.benchmark: [run.name for run in group.runs] for group in groups},
        drag_settings=sorted(settings, key=lambda s: (order.get(s, len(order)), s)),
        perception_kinds=sorted(kinds, key=lambda k: (kind_order.get(k, len(kind_order)), k)),
        warnings=warnings,
        rows=sorted(rows, key=lambda r: (r.scripted, r.label)),
    )


def diagnosis_row(label: str, key: ModelKey, found: _Results) -> DiagnosisRow:
    """One row's metrics from the runs gathered for its key."""
    decided = [r for r in found.episodes if r.outcome in DETERMINATE]
    pass_at_1: dict[str, Rate] = {}
    start = end = None
    by_setting: dict[str, list[drag.DragRun]] = defaultdict(list)
    for run in found.drags:
        by_setting[run.job.setting or ""].append(run)
    for setting, runs in by_setting.items():
        cell = drag.drag_cell(drag.ALL, runs)
        if cell.pass_at_k:
            pass_at_1[setting] = Rate(value=cell.pass_at_k[0].unbiased, n=cell.runs)
        if setting == START_END_SETTING:
            start, end = _rate(cell.start_accuracy, cell.runs), _rate(cell.end_accuracy, cell.start_passes)
    return DiagnosisRow(
        label=label,
        agent=key.agent,
        scripted=key.scripted,
        labels=found.labels,
        models=found.models,
        composite_sr=success_rate([r for r in decided if r.mode == "composite"]),
        primitive_sr=success_rate([r for r in decided if r.mode == "primitive"]),
        gap=sr_gap(decided),
        drag_pass_at_1=pass_at_1,
        drag_start_accuracy=start,
        drag_end_accuracy=end,
        perception=perception_rates(found.answers),
    )


def perception_rates(runs: Sequence[perception.PerceptionRun]) -> dict[str, PerceptionRate]:
    """Both accuracies per item kind and over ``ALL``, for the groups with scored runs."""
    groups = {kind: [r for r in runs if r.kind == kind] for kind in sorted({r.kind for r in runs})}
    rates = {}
    for group, members in (groups | {perception.ALL: list(runs)}).items():
        cell = perception.perception_cell(group, None, members)
        normalized, strict = cell.normalized.rate, cell.strict.rate
        if normalized is not None and strict is not None:
            rates[group] = PerceptionRate(normalized=normalized, strict=strict, n=cell.scored)
    return rates


def success_rate(decided: Sequence[JobRow]) -> Rate | None:
    """Passed / jobs with a verdict; None without any."""
    return Rate(value=sum(r.outcome == "passed" for r in decided) / len(decided), n=len(decided)) if decided else None


def sr_gap(decided: Sequence[JobRow]) -> Gap | None:
    """Composite SR minus primitive SR of one model's decided episode jobs; None unless both modes have some.

    Seeds pair the two modes: with two or more seeds decided in both, the gap is the mean of the per-seed
    gaps with a t interval (seed-to-seed spread is the noise a rerun would show); else the pooled difference.
    """
    composite = [r for r in decided if r.mode == "composite"]
    primitive = [r for r in decided if r.mode == "primitive"]
    if not composite or not primitive:
        return None
    seeds = sorted({r.seed for r in composite} & {r.seed for r in primitive})
    if len(seeds) < 2:
        pooled = _sr(composite) - _sr(primitive)
        return Gap(points=pooled * 100, half_width=None, seeds=len(seeds))
    gaps = [_sr([r for r in composite if r.seed == s]) - _sr([r for r in primitive if r.seed == s]) for s in seeds]
    interval = mean_interval(gaps)
    half = None if interval.half_width is None else interval.half_width * 100
    return Gap(points=interval.mean * 100, half_width=half, seeds=len(seeds))


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


def _sr(decided: Sequence[JobRow]) -> float:
    return statistics.fmean(r.outcome == "passed" for r in decided)


def _rate(value: float | None, n: int) -> Rate | None:
    return None if value is None else Rate(value=value, n=n)
