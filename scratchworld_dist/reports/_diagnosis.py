"""The diagnosis table's rows and columns, and what a kind adds to it (``DiagnosisPart``): one row per model across
benchmarks, where its composite episodes fail and why.

Each kind with a part brings its cells (the episodes' composite and primitive SR and their gap, what GUI control
costs; the drag benchmark's Pass@1, can the model place one drag; the perception benchmark's accuracy, can it
read the workspace), the table axes its columns depend on, and its own report as a section. The row, table and
report models are built from the installed kinds' parts, each part's model a base of them (``diagnosis_models``),
so the JSON schema lists every kind's fields as the core's own. Rows are matched by model identity
(``_model_identity``), never by label; a model without results in a benchmark has no value there (shown as a
dash, never as 0). Every rate is over runs with a verdict: error runs are left out, as in each benchmark's own
report, which has their counts.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING, Any, Protocol

from pydantic import BaseModel, ConfigDict, JsonValue, create_model

from scratchworld_dist.reports._render import ReportFormat
from scratchworld_dist.reports._run_groups import RunGroup

MISSING = "\u2013"
"""An en dash: the model has no result there (never shown as 0)."""


class Rate(BaseModel):
    """A share and how many runs it is over."""

    value: float
    n: int


def rate_cell(rate: Rate | None) -> str:
    return MISSING if rate is None else f"{pct(rate.value)} (n={rate.n})"


def pct(value: float) -> str:
    return f"{value * 100:.1f}%"


def optional_rate(value: float | None, n: int) -> Rate | None:
    return None if value is None else Rate(value=value, n=n)


class DiagnosisPart(Protocol):
    """What a kind adds to the report over runs of several kinds: cells per model, and its own section.

    Its three models become bases of the diagnosis's models (``diagnosis_models``): their fields are the row's,
    the table's and the report's, named once across the installed kinds, each with a default (a model with no
    results of the kind, a report without its runs)."""

    cells_model: type[BaseModel]
    """Its cells: fields of the diagnosis row (``composite_sr``...), each defaulting to "no result"."""

    axes_model: type[BaseModel] | None
    """Fields of the diagnosis table its columns depend on (the drag settings seen); None: it has none."""

    section_model: type[BaseModel]
    """One field of the diagnosis report, named as the report's JSON names its section (``episodes``), holding
    its own report (None when the runs hold none of its kind)."""

    runs_label: str
    """How the table's header names its runs (``Episode runs``)."""

    definitions: str
    """What its cells mean, for the table's definitions."""

    def units(self, group: RunGroup) -> list[tuple[str, Any]]:
        """What its cells are computed from, each with the job id that says whose model it is."""
        ...

    def cells(self, units: Sequence[Any]) -> BaseModel:
        """One model's cells (a ``cells_model``) from its units."""
        ...

    def axes(self, units: Sequence[Any]) -> BaseModel | None:
        """Its axes (an ``axes_model``) over every model's units; None when it has none."""
        ...

    def header(self, table: Any) -> list[str]:
        """Its column headers; ``table`` is the diagnosis table, an instance of its ``axes_model``."""
        ...

    def row(self, row: Any, table: Any) -> list[str]:
        """Its cells as text; ``row`` is a diagnosis row, an instance of its ``cells_model``."""
        ...

    def section(self, group: RunGroup) -> BaseModel:
        """Its own report over the group's runs (already loaded and checked for merging)."""
        ...

    def render_section(self, section: Any, fmt: ReportFormat, group: RunGroup) -> str:
        """That report as Markdown (``md``) or an HTML fragment (``html``)."""
        ...


class DiagnosisRowCore(BaseModel):
    """What every diagnosis row holds, whichever kinds there are: whose row it is."""

    model_config = ConfigDict(extra="allow")

    label: str
    agent: str
    scripted: bool
    labels: list[str]
    """Every model label the runs gave it (several when runs named one model differently)."""

    models: list[dict[str, JsonValue]]
    """The identity of each of its models (empty for a scripted agent)."""


class DiagnosisTableCore(BaseModel):
    """What every diagnosis table holds before the kinds' axes (its warnings and rows follow them)."""

    model_config = ConfigDict(extra="allow")

    version: int = 1
    runs: dict[str, list[str]]
    """Per benchmark (tasks, drag, perception), the run directories read, as ``name (path)``."""

    if TYPE_CHECKING:  # declared by the built model (``models_of``), after the kinds' axes
        warnings: list[str]
        rows: list[DiagnosisRowCore]


class DiagnosisReportCore(BaseModel):
    """What every diagnosis report holds before the kinds' sections."""

    model_config = ConfigDict(extra="allow")

    version: int = 1
    diagnosis: DiagnosisTableCore

    @property
    def warnings(self) -> list[str]:
        """The table's and every section's."""
        sections = [getattr(self, name) for name in self.model_fields_set if name not in ("version", "diagnosis")]
        return self.diagnosis.warnings + [w for s in sections if s is not None for w in getattr(s, "warnings", [])]


_ROW_DOC = """One model (or scripted agent) across the benchmarks given; a missing value means no results there.

Each kind's diagnosis part fills its own cells (``KindReport.diagnosis``): the built-in kinds' are the
fields below; a plugin kind's are fields of the row too (its part's ``cells_model``)."""

_TABLE_DOC = "The diagnosis over runs of several benchmarks."

_REPORT_DOC = """The diagnosis table and the report of each benchmark given (None: no run of it). The built-in kinds'
sections are the fields below; a plugin kind's is a field too (its part's ``section_model``)."""


@dataclass(frozen=True)
class DiagnosisModels:
    """The diagnosis's models for a set of kinds' parts (each a subclass of its core and of the parts' models)."""

    row: type[DiagnosisRowCore]
    table: type[DiagnosisTableCore]
    report: type[DiagnosisReportCore]


def section_field(part: DiagnosisPart) -> str:
    """The report field that holds ``part``'s section: its ``section_model``'s one field."""
    return next(iter(part.section_model.model_fields))


def models_of(parts: tuple[DiagnosisPart, ...]) -> DiagnosisModels:
    """The row, table and report models of ``parts``, built once per set of the parts' models (a part made anew
    at each call gets the same models, so a row of one call fits a table of the next)."""
    _check(
        parts,
        [p.cells_model for p in parts],
        [p.axes_model for p in parts if p.axes_model],
        [p.section_model for p in parts],
    )
    return _built(tuple((part.cells_model, part.axes_model, part.section_model) for part in parts))


@cache
def _built(models: tuple[tuple[type[BaseModel], type[BaseModel] | None, type[BaseModel]], ...]) -> DiagnosisModels:
    cells = [cell for cell, _, _ in models]
    axes = [axis for _, axis, _ in models if axis is not None]
    sections = [section for _, _, section in models]
    # Pydantic orders fields from the last base in the MRO to the class itself: the core's first, then each
    # part's in the kinds' order, then the fields declared here (the table's warnings and rows after the axes).
    row = create_model(
        "DiagnosisRow", __base__=(*reversed(cells), DiagnosisRowCore), __doc__=_ROW_DOC, __module__=__name__
    )
    table = create_model(
        "DiagnosisTable",
        __base__=(*reversed(axes), DiagnosisTableCore),
        __doc__=_TABLE_DOC,
        __module__=__name__,
        warnings=(list[str], ...),
        rows=(list[row], ...),  # type: ignore[valid-type]
    )
    report = create_model(
        "DiagnosisReport",
        __base__=(*reversed(sections), DiagnosisReportCore),
        __doc__=_REPORT_DOC,
        __module__=__name__,
        diagnosis=(table, ...),  # keeps the core's place, second
    )
    return DiagnosisModels(row=row, table=table, report=report)


def _check(
    parts: Sequence[DiagnosisPart],
    cells: Sequence[type[BaseModel]],
    axes: Sequence[type[BaseModel]],
    sections: Sequence[type[BaseModel]],
) -> None:
    """Each part's fields are optional and named once (with the core's), and its section is one field."""
    for part, section in zip(parts, sections, strict=True):
        if len(section.model_fields) != 1:
            raise TypeError(f"{type(part).__name__}.section_model must have one field (its section), not {section}")
    taken = (
        (set(DiagnosisRowCore.model_fields), cells),
        ({*DiagnosisTableCore.model_fields, "warnings", "rows"}, axes),
        ({*DiagnosisReportCore.model_fields, "warnings"}, sections),
    )
    for core, models in taken:
        seen = dict.fromkeys(core, "the core")
        for model in models:
            for name, field in model.model_fields.items():
                if field.is_required():
                    raise TypeError(f"{model.__name__}.{name} needs a default (a model without results there)")
                if name in seen:
                    raise TypeError(f"{model.__name__}.{name} is a field of {seen[name]} already")
                seen[name] = model.__name__
