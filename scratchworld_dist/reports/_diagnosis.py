"""The diagnosis table's rows and columns, and what a kind adds to it (``DiagnosisPart``): one row per model across
benchmarks, where its composite episodes fail and why.

Composite and primitive SR come from episode runs, the gap between them is what GUI control costs, and
the diagnostic benchmarks say where that cost arises: the drag benchmark (can the model place one drag)
and the perception benchmark (can it read the workspace). Rows are matched by model identity
(``_model_identity``), never by label; a model without results in a benchmark has no value there (shown
as a dash, never as 0). Every rate is over runs with a verdict: error runs are left out, as in each
benchmark's own report, which has their counts.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Protocol

from pydantic import BaseModel, ConfigDict, JsonValue

from scratchworld_dist.reports._diagnosis_cells import Rate
from scratchworld_dist.reports._render import ReportFormat
from scratchworld_dist.reports._run_groups import RunGroup


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

    Each kind's diagnosis part fills its own cells (``KindReport.diagnosis``): the built-in kinds' are the
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


class DiagnosisPart(Protocol):
    """What a kind adds to the report over runs of several kinds: cells per model, and its own section."""

    section_field: str
    """The field of ``DiagnosisReport`` that holds its section (a plugin's: an extra field of that name)."""

    runs_label: str
    """How the table's header names its runs (``Episode runs``)."""

    definitions: str
    """What its cells mean, for the table's definitions."""

    def units(self, group: RunGroup) -> list[tuple[str, Any]]:
        """What its cells are computed from, each with the job id that says whose model it is."""
        ...

    def cells(self, units: Sequence[Any]) -> dict[str, Any]:
        """One model's cells (fields of ``DiagnosisRow``) from its units."""
        ...

    def axes(self, units: Sequence[Any]) -> dict[str, list[str]]:
        """Fields of ``DiagnosisTable`` its columns depend on (the drag settings seen), over every model's units."""
        ...

    def header(self, table: DiagnosisTable) -> list[str]: ...

    def row(self, row: DiagnosisRow, table: DiagnosisTable) -> list[str]: ...

    def section(self, group: RunGroup) -> BaseModel:
        """Its own report over the group's runs (already loaded and checked for merging)."""
        ...

    def render_section(self, section: Any, fmt: ReportFormat, group: RunGroup) -> str:
        """That report as Markdown (``md``) or an HTML fragment (``html``)."""
        ...
