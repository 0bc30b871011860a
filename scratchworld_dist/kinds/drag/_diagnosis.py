"""The drag columns of the diagnosis table: can the model place one drag (Pass@1 per setting, and where its
unaided drags start and end)."""

from __future__ import annotations

import html
from collections import defaultdict
from collections.abc import Sequence
from typing import Any

from pydantic import BaseModel, SerializeAsAny

import scratchworld_dist.kinds.drag._metrics as drag
from scratchworld_dist.kinds.drag._table import drag_table_of, render_drag_markdown
from scratchworld_dist.reports import Rate, ReportFormat, RunGroup, optional_rate, rate_cell

START_END_SETTING = "baseline"
"""The drag setting whose start and end accuracy the table shows: the unaided one, as the agent acts."""


class DragCells(BaseModel):
    """The drag cells of a diagnosis row."""

    drag_pass_at_1: dict[str, Rate] = {}
    """Per drag setting: the unbiased Pass@1 (mean over tasks of passes / runs)."""

    drag_start_accuracy: Rate | None = None
    """In the drag part's start-and-end setting: runs pressing inside the start region / runs."""

    drag_end_accuracy: Rate | None = None
    """In that setting: connected / good starts."""


class DragAxes(BaseModel):
    """What the drag columns of the diagnosis table depend on."""

    drag_settings: list[str] = []


class DragSection(BaseModel):
    """Table 2's place in the report over several kinds."""

    drag: SerializeAsAny[BaseModel] | None = None
    """The drag kind's table (``kinds.drag.DragTable``)."""


class DragDiagnosis:
    """Each model's drag runs, per setting."""

    cells_model = DragCells
    axes_model = DragAxes
    section_model = DragSection
    runs_label = "Drag runs"
    definitions = (
        "Drag Pass@1 = mean over tasks of passes / runs (the unbiased estimator at k = 1), per setting; start and "
        f"end accuracy are of the {START_END_SETTING} setting, the unaided one: start = runs pressing inside the "
        "start region / runs, end = connected / good starts (n = good starts)."
    )

    def units(self, group: RunGroup) -> list[tuple[str, Any]]:
        jobs = [row for run in group.runs for row in run.rows]
        runs, _ = drag.join_runs(jobs, group.tables["drags"])  # type: ignore[arg-type]
        return [(run.job.job_id, run) for run in runs]

    def cells(self, units: Sequence[drag.DragRun]) -> DragCells:
        pass_at_1: dict[str, Rate] = {}
        start = end = None
        by_setting: dict[str, list[drag.DragRun]] = defaultdict(list)
        for run in units:
            by_setting[run.job.setting or ""].append(run)
        for setting, runs in by_setting.items():
            cell = drag.drag_cell(drag.ALL, runs)
            if cell.pass_at_k:
                pass_at_1[setting] = Rate(value=cell.pass_at_k[0].unbiased, n=cell.runs)
            if setting == START_END_SETTING:
                start = optional_rate(cell.start_accuracy, cell.runs)
                end = optional_rate(cell.end_accuracy, cell.start_passes)
        return DragCells(drag_pass_at_1=pass_at_1, drag_start_accuracy=start, drag_end_accuracy=end)

    def axes(self, units: Sequence[drag.DragRun]) -> DragAxes:
        order = {s: i for i, s in enumerate(drag.SETTINGS)}
        settings = {run.job.setting or "" for run in units}
        return DragAxes(drag_settings=sorted(settings, key=lambda s: (order.get(s, len(order)), s)))

    def header(self, table: DragAxes) -> list[str]:
        header = [f"drag Pass@1 {setting}" for setting in table.drag_settings]
        return [*header, f"drag start acc. ({START_END_SETTING})", f"drag end acc. ({START_END_SETTING})"]

    def row(self, row: DragCells, table: DragAxes) -> list[str]:
        cells = [rate_cell(row.drag_pass_at_1.get(setting)) for setting in table.drag_settings]
        return [*cells, rate_cell(row.drag_start_accuracy), rate_cell(row.drag_end_accuracy)]

    def section(self, group: RunGroup) -> drag.DragTable:
        return drag_table_of(group.runs, group.warnings, group.tables["drags"])  # type: ignore[arg-type]

    def render_section(self, section: drag.DragTable, fmt: ReportFormat, group: RunGroup) -> str:
        text = render_drag_markdown(section)
        return text if fmt == "md" else f"<pre>{html.escape(text)}</pre>"


DIAGNOSIS = DragDiagnosis()
