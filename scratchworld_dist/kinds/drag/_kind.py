"""The single-step drag benchmark (``benchmark: drag``): an agent is shown the editor once and answers with
one drag, judged by where it pressed and released against the exact regions of the expected connection."""

from __future__ import annotations

import html
from collections.abc import Mapping, Sequence
from pathlib import Path
from types import MappingProxyType
from typing import ClassVar

from pydantic import BaseModel

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds._single_answer import SingleAnswerKind
from scratchworld_dist.kinds.drag._plan import DragBody, DragSweep, plan_drag_jobs, read_drag_task
from scratchworld_dist.kinds.drag._rows import DragRow, drag_row
from scratchworld_dist.kinds.drag.items import DragTask, load_drag_suite
from scratchworld_dist.reports import DiagnosisPart, ReportFormat
from scratchworld_dist.sweep import (
    JobSpec,
    Notice,
    RunPlan,
    SuiteInfo,
    SweepConfig,
    present_suites,
    suite_hash,
    wanted_ids,
)
from workers.contract import HarnessFingerprint, JobResult, WorkerJob
from workers.kinds.drag import DragAttempt, DragSpec


class DragKind(SingleAnswerKind):
    """Model x setting x task x seed: one drag each, in a fresh editor framed on the task's view."""

    name = "drag"
    rank = 10
    title = "single-step drag"
    needs_browser = True
    tables: ClassVar[Mapping[str, type[BaseModel]]] = MappingProxyType({"drags": DragRow})
    config_section: type[BaseModel] | None = DragSweep
    regrade_refusal: str | None = "a drag benchmark run stores drags, not projects: nothing to regrade"

    def plan(self, config: SweepConfig, harness: HarnessFingerprint, notice: Notice) -> RunPlan:
        """The suite's tasks (and those of each optional suite that is present) with a view, selected by
        ``tasks.ids`` and ``drag.types``; a task without a view is left out, named."""
        section = config.section(self.name, DragSweep)
        suites = present_suites(
            config.suite, section.optional_suites, load_drag_suite, notice, benchmark="drag", item="task"
        )
        tasks: list[DragTask] = []
        for suite in suites:
            for problem in suite.problems:
                if problem.effect == "skipped":
                    notice(f"drag: {suite.name}: {problem} (left out)")
            for task in suite.tasks:
                if task.view is None:
                    notice(f"drag: {suite.name} {task.id} has no usable view and is left out")
                    continue
                tasks.append(task)
        wanted = wanted_ids([task.id for task in tasks], config.tasks.ids, benchmark="drag", item="task", suites=suites)
        types = section.types
        tasks = [t for t in tasks if (not wanted or t.id in wanted) and (not types or t.type in types)]
        if not tasks:
            raise ConfigError(f"the selection matches no drag task of {', '.join(s.name for s in suites)}")
        contents = [read_drag_task(task, config.project_limits) for task in tasks]
        info = SuiteInfo(
            name=" + ".join(s.name for s in suites),
            kind=suites[0].kind,
            root=str(suites[0].root),
            hash=suite_hash(contents),
            tasks=len(tasks),
        )
        jobs = plan_drag_jobs(
            config.model_specs(),
            section.settings,
            self.agents(config),
            contents,
            config.seeds,
            element_list=section.element_list,
            observation=config.primitive,
            llm=config.llm,
            project_limits=config.project_limits,
            harness=harness.digest,
            model_cache=config.model_cache,
        )
        return RunPlan(config=config, harness=harness, suite=info, contents=contents, jobs=list(jobs))

    def worker_job(self, job: JobSpec, attempt: int, timeout_s: float) -> WorkerJob:
        body = job.body
        if not isinstance(body, DragBody):
            raise ValueError(f"job {job.job_id} is not a drag job")
        return DragSpec(
            **job.agent_header(attempt, timeout_s),
            setting=body.setting,
            element_list=body.element_list,
            observation=body.observation,
        )

    def own_rows(self, job: JobSpec, result: JobResult, artifact_dir: str | None) -> dict[str, list[BaseModel]]:
        drag = result.detail
        if not isinstance(drag, DragAttempt):
            return {"drags": []}
        annotated = None
        if drag.annotated_sha256 is not None:
            annotated = f"{artifact_dir or ''}/images/{drag.annotated_sha256}.png".lstrip("/")
        return {"drags": [drag_row(job, result, annotated)]}

    def holds(self, run_dir: Path) -> bool:
        from scratchworld_dist.kinds.drag._table import is_drag_run

        return is_drag_run(run_dir)

    def render_report(self, data: BaseModel, fmt: ReportFormat) -> str:
        from scratchworld_dist.kinds.drag._table import DragTable, render_drag

        assert isinstance(data, DragTable)
        return render_drag(data, fmt)

    def report_model(self) -> type[BaseModel]:
        from scratchworld_dist.kinds.drag._table import DragTable

        return DragTable

    def report_data(self, run_dirs: Sequence[Path], *, force: bool) -> BaseModel:
        from scratchworld_dist.kinds.drag._table import build_drag_report

        return build_drag_report(list(run_dirs), force=force)

    def diagnosis(self) -> DiagnosisPart | None:
        # Reports import the statistics stack: only a report asks for them.
        from scratchworld_dist.kinds.drag._diagnosis import DIAGNOSIS

        return DIAGNOSIS

    def report_html(self, run_dir: Path) -> tuple[str, list[str]]:
        from scratchworld_dist.kinds.drag._table import build_drag_report, render_drag_markdown

        drag = build_drag_report([run_dir])
        return f"<pre>{html.escape(render_drag_markdown(drag))}</pre>", drag.warnings


DRAG = DragKind()
"""The registered kind (entry point ``drag``)."""
