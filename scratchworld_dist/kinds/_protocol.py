"""What a job kind is to the driver: one benchmark's config checks, planning, jobs, rows and report.

The core (sweep config, planning, the run loop, results, reports, regrades, the viewer) never asks which
benchmark it holds: it looks the kind up by name (``job_kind``) and calls it. The name is the sweep
config's ``benchmark:`` value and the ``benchmark`` column of every job row.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Protocol

from pydantic import BaseModel

from workers.contract import AgentRef, HarnessFingerprint, JobResult, ModelSpec, WorkerJob

if TYPE_CHECKING:
    from scratchworld_dist._run_plan import ItemContent, RunPlan
    from scratchworld_dist.reports import DiagnosisRow, DiagnosisTable, ReportFormat, RunGroup
    from scratchworld_dist.results import RunStore
    from scratchworld_dist.sweep import JobSpec, SweepConfig

Notice = Callable[[str], None]
"""Where planning says what it left out (a missing optional suite, an unusable task)."""


class AttemptPanel(BaseModel):
    """A kind's part of one attempt on the viewer's job page, above its tests."""

    title: str
    html: str
    """The panel's body: an HTML fragment, every value in it escaped by the kind."""

    instruction: str | None = None
    """What the page shows as the job's instruction instead of the task's (a perception item's question)."""

    shows_project: bool = True
    """Whether the attempt's final project belongs on the page (False when its jobs edit no project)."""


class JobKind(Protocol):
    """One benchmark, as the driver runs and reports it."""

    name: str
    """The config's ``benchmark:`` value, the rows' ``benchmark`` column and the entry point's name."""

    title: str
    """How messages name the kind (``task episodes``, ``single-step drag``...)."""

    needs_browser: bool
    """Whether its jobs open an editor (admission and warm editors count only those that do)."""

    episodes: bool
    """Whether its jobs are agent episodes (steps, a final project, tests): the run plots and the exports
    (leaderboard, upstream submission, ATIF) are made of those."""

    tables: Mapping[str, type[BaseModel]]
    """Result tables of its own besides ``jobs``, ``steps`` and ``tests``: folder name and row model (with
    ``job_id`` and ``attempt``; a run holds the tables of its kind)."""

    config_section: type[BaseModel] | None
    """The model of its section of a sweep config, under its ``section_key`` (``drag:``); None: it has none.

    A kind may name that key in a ``config_key`` attribute when its name will not do (the task episodes'
    ``episodes:``, since ``tasks:`` is the selection every kind reads); without one it is the kind's name, so a
    plugin written before the attribute existed keeps its section where it was. A section model may list in a
    ``former_keys`` class attribute the top-level keys it took over (they still read there, moved into it with a
    notice: ``scratchworld_dist.sweep``), and in ``resume_free`` (pydantic's ``exclude`` form) what may change
    between sessions of one run without making it another sweep."""

    regrade_refusal: str | None
    """Why its runs cannot be regraded (None: they store projects a regrade evaluates again)."""

    def check_agent(self, agent: AgentRef) -> None:
        """Raise ``AgentUnavailableError`` naming the problem unless ``agent`` acts in this kind as given."""
        ...

    def check_sweep(self, config: SweepConfig) -> None:
        """Raise ``ValueError`` naming the problem unless the sweep's other fields fit this kind."""
        ...

    def needs_model(self, config: SweepConfig) -> bool:
        """Whether any agent of the sweep calls a model (the sweep then needs one)."""
        ...

    def helper_models(self, agent: AgentRef) -> list[ModelSpec]:
        """Models ``agent`` calls besides the sweep's ``models`` (a grounding model...), as its params name them."""
        ...

    def plan(self, config: SweepConfig, harness: HarnessFingerprint, notice: Notice) -> RunPlan:
        """The sweep's items read once and its job matrix, under ``harness``."""
        ...

    def worker_job(self, job: JobSpec, attempt: int, timeout_s: float) -> WorkerJob:
        """What a worker is sent for one attempt of ``job``."""
        ...

    def own_rows(self, job: JobSpec, result: JobResult, artifact_dir: str | None) -> dict[str, list[BaseModel]]:
        """The rows of this kind's own ``tables`` for one attempt (``artifact_dir``: where its files went)."""
        ...

    def store_shared(self, store: RunStore, contents: Sequence[ItemContent]) -> None:
        """Store once per run what many of its jobs' rows refer to (a perception item's screenshot)."""
        ...

    def holds(self, run_dir: Path) -> bool:
        """Whether a run directory written before rows named their benchmark holds this kind's jobs."""
        ...

    def report(self, run_dirs: Sequence[Path], fmt: ReportFormat, *, force: bool) -> tuple[str, list[str]]:
        """This kind's own report over its runs, and its warnings (``RunDirError`` when they cannot be merged)."""
        ...

    def report_data(self, run_dirs: Sequence[Path], *, force: bool) -> BaseModel:
        """This kind's report over its runs as data: the model ``report`` renders (its JSON format is its dump)."""
        ...

    def report_model(self) -> type[BaseModel]:
        """The model ``report_data`` returns (its JSON schema is published with the reports')."""
        ...

    def report_html(self, run_dir: Path) -> tuple[str, list[str]]:
        """The body of one run's page in the viewer (HTML, escaped), and its warnings."""
        ...

    def attempt_panel(self, rows: Mapping[str, Sequence[BaseModel]], root: str, run_dir: Path) -> AttemptPanel | None:
        """What the viewer's job page shows of one attempt's rows in this kind's ``tables`` (None: nothing);
        ``root`` is the run directory as the page links to it (``../``), ``run_dir`` where it is on disk (for what
        the rows only refer to: the audit reads its run's manifest to show the programs a row names)."""
        ...

    def diagnosis(self) -> DiagnosisPart | None:
        """Its columns of the diagnosis table and its section of the report over several kinds (None: none)."""
        ...


def section_key(kind: JobKind) -> str:
    """The key of ``kind``'s section in a sweep config: its ``config_key`` when it names one, else its name."""
    key = getattr(kind, "config_key", None)
    return key if isinstance(key, str) and key else kind.name


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
