"""The perception columns of the diagnosis table: can the model read the workspace (accuracy per item kind,
both scorings)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from pydantic import BaseModel, SerializeAsAny

import scratchworld_dist.kinds.perception._metrics as perception
from scratchworld_dist.kinds.perception._table import perception_blocks, perception_table_of
from scratchworld_dist.reports import MISSING, ReportFormat, RunGroup, blocks_html, blocks_markdown, pct
from workers.kinds.perception import PERCEPTION_KINDS


class PerceptionRate(BaseModel):
    """Perception accuracy both ways over the same scored runs."""

    normalized: float
    strict: float
    n: int


class PerceptionCells(BaseModel):
    """The perception cells of a diagnosis row."""

    perception: dict[str, PerceptionRate] = {}
    """Per item kind, and ``ALL``."""


class PerceptionAxes(BaseModel):
    """What the perception columns of the diagnosis table depend on."""

    perception_kinds: list[str] = []


class PerceptionSection(BaseModel):
    """The perception report's place in the report over several kinds."""

    perception: SerializeAsAny[BaseModel] | None = None
    """The perception kind's table (``kinds.perception.PerceptionTable``)."""


class PerceptionDiagnosis:
    """Each model's scored answers, per item kind."""

    cells_model = PerceptionCells
    axes_model = PerceptionAxes
    section_model = PerceptionSection
    runs_label = "Perception runs"
    definitions = (
        "Perception = accuracy per item kind and overall as normalized / strict (our reading of the answer / "
        "upstream's exact match), over the scored runs."
    )

    def units(self, group: RunGroup) -> list[tuple[str, Any]]:
        jobs = [row for run in group.runs for row in run.rows]
        runs, _ = perception.join_runs(jobs, group.tables["perception"])  # type: ignore[arg-type]
        return [(answered.job.job_id, answered) for answered in runs]

    def cells(self, units: Sequence[perception.PerceptionRun]) -> PerceptionCells:
        return PerceptionCells(perception=perception_rates(units))

    def axes(self, units: Sequence[perception.PerceptionRun]) -> PerceptionAxes:
        order = {k: i for i, k in enumerate(PERCEPTION_KINDS)}
        kinds = {answered.kind for answered in units}
        return PerceptionAxes(perception_kinds=sorted(kinds, key=lambda k: (order.get(k, len(order)), k)))

    def header(self, table: PerceptionAxes) -> list[str]:
        header = [f"perception {kind} (norm. / strict)" for kind in table.perception_kinds]
        return [*header, "perception overall (norm. / strict)"]

    def row(self, row: PerceptionCells, table: PerceptionAxes) -> list[str]:
        return [_cell(row.perception.get(kind)) for kind in [*table.perception_kinds, perception.ALL]]

    def section(self, group: RunGroup) -> perception.PerceptionTable:
        return perception_table_of(group.runs, group.warnings, group.tables["perception"])  # type: ignore[arg-type]

    def render_section(self, section: perception.PerceptionTable, fmt: ReportFormat, group: RunGroup) -> str:
        blocks = perception_blocks(section)
        return blocks_markdown(blocks) if fmt == "md" else blocks_html(blocks)


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


def _cell(rate: PerceptionRate | None) -> str:
    return MISSING if rate is None else f"{pct(rate.normalized)} / {pct(rate.strict)} (n={rate.n})"


DIAGNOSIS = PerceptionDiagnosis()
