"""The visual perception QA benchmark (``benchmark: perception``): an agent answers one question about a
static screenshot of the editor, scored strictly (upstream's exact match) and normalized (ours)."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import ClassVar

from pydantic import BaseModel

from scratchworld_dist.kinds._single_answer import SingleAnswerKind
from scratchworld_dist.kinds.perception._panel import answer_panel
from scratchworld_dist.kinds.perception._plan import (
    PerceptionContent,
    PerceptionSweep,
    plan_perception_jobs,
    select_perception_items,
)
from scratchworld_dist.kinds.perception._rows import PerceptionRow, perception_row
from scratchworld_dist.reports import DiagnosisPart, ReportFormat
from scratchworld_dist.results import SharedFiles, shared_image_path
from scratchworld_dist.sweep import ItemContent, JobSpec, Notice, RunPlan, SuiteInfo, SweepConfig, suite_hash
from scratchworld_dist.viewer import AttemptPanel
from workers.contract import HarnessFingerprint, JobResult, WorkerJob
from workers.kinds.perception import PerceptionAttempt, PerceptionSpec


class PerceptionKind(SingleAnswerKind):
    """Agent x model x item x seed: one answer each, about a screenshot; no browser."""

    name = "perception"
    rank = 20
    title = "perception"
    needs_browser = False
    tables: ClassVar[Mapping[str, type[BaseModel]]] = MappingProxyType({"perception": PerceptionRow})
    config_section: type[BaseModel] | None = PerceptionSweep
    regrade_refusal: str | None = "a perception benchmark run stores answers, not projects: nothing to regrade"

    def plan(self, config: SweepConfig, harness: HarnessFingerprint, notice: Notice) -> RunPlan:
        """The items of the suite (and of each optional suite that is present), selected by ``tasks.ids`` and
        ``perception.kinds``."""
        perception = config.section(self.name, PerceptionSweep)
        selection = select_perception_items(
            config.suite, perception.optional_suites, config.tasks.ids, perception.kinds, notice
        )
        contents = selection.contents
        info = SuiteInfo(
            name=selection.name, kind=selection.kind, root=str(selection.root), hash=suite_hash(contents),
            tasks=len(contents),
        )  # fmt: skip
        jobs = plan_perception_jobs(
            config.model_specs(),
            self.agents(config),
            contents,
            config.seeds,
            llm=config.llm,
            harness=harness.digest,
            model_cache=config.model_cache,
        )
        return RunPlan(config=config, harness=harness, suite=info, contents=contents, jobs=list(jobs))

    def worker_job(self, job: JobSpec, attempt: int, timeout_s: float) -> WorkerJob:
        return PerceptionSpec(
            **job.agent_header(attempt, timeout_s),
        )

    def own_rows(self, job: JobSpec, result: JobResult, artifact_dir: str | None) -> dict[str, list[BaseModel]]:
        return {"perception": [perception_row(job, result)] if isinstance(result.detail, PerceptionAttempt) else []}

    def store_shared(self, files: SharedFiles, contents: Sequence[ItemContent]) -> None:
        """Each item's screenshot, stored once in the run directory for all the jobs that show it."""
        for content in contents:
            if isinstance(content, PerceptionContent):
                png = content.payload.screenshot_png
                files.write_shared_image(shared_image_path(hashlib.sha256(png).hexdigest()), png)

    def holds(self, run_dir: Path) -> bool:
        from scratchworld_dist.kinds.perception._table import is_perception_run

        return is_perception_run(run_dir)

    def render_report(self, data: BaseModel, fmt: ReportFormat) -> str:
        from scratchworld_dist.kinds.perception._table import PerceptionTable, render_perception

        assert isinstance(data, PerceptionTable)
        return render_perception(data, fmt)

    def report_model(self) -> type[BaseModel]:
        from scratchworld_dist.kinds.perception._table import PerceptionTable

        return PerceptionTable

    def report_data(self, run_dirs: Sequence[Path], *, force: bool) -> BaseModel:
        from scratchworld_dist.kinds.perception._table import build_perception_report

        return build_perception_report(list(run_dirs), force=force)

    def diagnosis(self) -> DiagnosisPart | None:
        # Reports import the statistics stack: only a report asks for them.
        from scratchworld_dist.kinds.perception._diagnosis import DIAGNOSIS

        return DIAGNOSIS

    def report_html(self, run_dir: Path) -> tuple[str, list[str]]:
        from scratchworld_dist.kinds.perception._table import build_perception_report, perception_blocks
        from scratchworld_dist.reports import blocks_html

        perception = build_perception_report([run_dir])
        return blocks_html(perception_blocks(perception)), perception.warnings

    def attempt_panel(self, rows: Mapping[str, Sequence[BaseModel]], root: str, run_dir: Path) -> AttemptPanel | None:
        return answer_panel(rows, root)


PERCEPTION = PerceptionKind()
"""The registered kind (entry point ``perception``)."""
