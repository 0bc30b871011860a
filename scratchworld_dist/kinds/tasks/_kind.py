"""Task episodes (``benchmark: tasks``): an agent works on a task of a suite for up to ``episodes.max_steps``
steps, then the task's tests judge the project it leaves; the kind ``regrade`` evaluates again."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.kinds.base import Kind
from scratchworld_dist.kinds.tasks._plan import EpisodeBody, EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.kinds.tasks._settings import EPISODES_KEY, EpisodeSweep
from scratchworld_dist.kinds.tasks._token_rates import EPISODE_RATES
from scratchworld_dist.memory import JobItems, offline_source, source_digest
from scratchworld_dist.reports import DiagnosisPart, ReportFormat, plots_html
from scratchworld_dist.results import JobRow
from scratchworld_dist.suites import Suite, load_suite, stability_marks
from scratchworld_dist.sweep import (
    NO_MODEL,
    JobSpec,
    Notice,
    RunPlan,
    SuiteInfo,
    SweepConfig,
    TokenRates,
    suite_hash,
)
from scratchworld_dist.viewer import RunComparison
from workers.agent_api import agent_class, agent_code, agent_params, extra_models
from workers.contract import AgentRef, EpisodeClock, HarnessFingerprint, Mode, ModelSpec, WorkerJob
from workers.kinds.tasks import EpisodeSpec


class TasksKind(Kind):
    """Multi-step episodes on a task suite (ours or an upstream clone), in composite or primitive mode."""

    name = "tasks"
    rank = 0
    title = "task episodes"
    needs_browser = True
    episodes = True
    config_section = EpisodeSweep
    config_key = EPISODES_KEY  # not its name: ``tasks:`` is the selection every kind reads
    compares_runs = True
    regrade_refusal: str | None = None

    def check_sweep(self, config: SweepConfig) -> None:
        agent, episodes = agent_class(config.agent.name), episode_settings(config)
        supported = getattr(agent, "modes", ("composite", "primitive"))
        unsupported = [mode for mode in episodes.modes if mode not in supported]
        if unsupported:
            raise ValueError(f"agent {config.agent.name!r} cannot act in {', '.join(unsupported)} mode")
        if getattr(agent, "real_time", False) and (episodes.episode_clock or EpisodeClock()).mode != "real":
            raise ValueError(f"agent {config.agent.name!r} acts on the wall clock: episodes.episode_clock must be real")
        if getattr(agent, "exclusive", False) and config.ray.address is not None:
            raise ValueError(f"agent {config.agent.name!r} runs on this machine, one job at a time: drop ray.address")
        learns = getattr(agent, "learns", False)
        if episodes.memory is not None and not learns:
            raise ValueError(f"memory is for agents that learn across jobs; {config.agent.name!r} does not")
        if learns and episodes.memory is None:
            raise ValueError(
                f"agent {config.agent.name!r} learns across jobs: give episodes.memory (kind: online or offline)"
            )

    def token_rates(self, mode: str) -> TokenRates:
        return EPISODE_RATES.get(mode) or super().token_rates(mode)

    def helper_models(self, agent: AgentRef) -> list[ModelSpec]:
        return extra_models(agent_params(agent_class(agent.name), agent))

    def plan(self, config: SweepConfig, harness: HarnessFingerprint, notice: Notice) -> RunPlan:
        episodes = episode_settings(config)
        suite, contents = selected_tasks(config, episodes.oracle_trajectories)
        tasks = [content.task for content in contents]
        synthetic = episodes.synthetic
        unknown = sorted(set(synthetic.tasks or []) - {t.id for t in tasks}) if synthetic is not None else []
        if unknown:
            raise ConfigError(f"episodes.synthetic.tasks names task(s) not in the selection: {', '.join(unknown)}")
        info = SuiteInfo(
            name=suite.name,
            kind=suite.kind,
            root=str(suite.root),
            hash=suite_hash(contents),
            tasks=len(tasks),
            stability=stability_marks(suite, tasks),
        )
        found = agent_class(config.agent.name)
        sources = offline_sources(config) if episodes.memory is not None else {}
        matrix = EpisodeMatrix(
            models=config.model_specs(),
            modes=episodes.modes,
            agent=config.agent,
            tasks=contents,
            seeds=config.seeds,
            max_steps=episodes.max_steps,
            observation=config.primitive,
            llm=config.llm,
            project_limits=config.project_limits,
            harness=harness.digest,
            synthetic=synthetic,
            agent_code=agent_code(found),
            extra_models=extra_models(agent_params(found, config.agent)),
            memory=episodes.memory,
            memory_sources={stream: source_digest(entries) for stream, entries in sources.items()},
            episode_clock=episodes.episode_clock or default_episode_clock(found),
            model_cache=config.model_cache,
            record=config.record,
        )
        jobs = list(plan_jobs(matrix))
        return RunPlan(
            config=config,
            harness=harness,
            suite=info,
            contents=contents,
            jobs=jobs,
            memory=episodes.memory,
            memory_sources=sources,
            synthetic=synthetic,
        )

    def worker_job(self, job: JobSpec, attempt: int, timeout_s: float) -> WorkerJob:
        body = job.body
        if not isinstance(body, EpisodeBody):
            raise ValueError(f"job {job.job_id} is not an episode")
        return EpisodeSpec(
            **job.agent_header(attempt, timeout_s),
            mode=body.mode,
            max_steps=body.max_steps,
            observation=body.observation,
            project_limits=body.project_limits,
            memory=job.memory_snapshot,
            episode_clock=body.episode_clock,
            record=body.record,
        )

    def holds(self, run_dir: Path) -> bool:
        return True  # the default kind: an older run no other kind claims holds episodes

    def report(self, run_dirs: Sequence[Path], fmt: ReportFormat, *, force: bool) -> tuple[str, list[str]]:
        # Reports import the plotting and statistics stacks: only a report asks for them.
        from scratchworld_dist.kinds.tasks.report import build_report, render, report_plots

        members = list(run_dirs)
        report = build_report(members, force=force)
        plots = report_plots(members, force=force) if fmt == "html" else []  # drawing is slow: only for a page
        return render(report, fmt, plots), report.warnings

    def tracker_files(self, run_dir: Path) -> dict[str, bytes]:
        from scratchworld_dist.kinds.tasks.exports._leaderboard import leaderboard_files

        return leaderboard_files([run_dir])[0]

    def report_model(self) -> type[BaseModel]:
        from scratchworld_dist.kinds.tasks.report import RunReport

        return RunReport

    def schemas(self) -> dict[str, type[BaseModel]]:
        from atif import Trajectory

        return {**super().schemas(), "atif-v1.8": Trajectory}  # what export --format atif writes

    def report_data(self, run_dirs: Sequence[Path], *, force: bool) -> BaseModel:
        from scratchworld_dist.kinds.tasks.report import build_report

        return build_report(list(run_dirs), force=force)

    def diagnosis(self) -> DiagnosisPart | None:
        # Reports import the statistics stack: only a report asks for them.
        from scratchworld_dist.kinds.tasks._diagnosis import DIAGNOSIS

        return DIAGNOSIS

    def report_html(self, run_dir: Path) -> tuple[str, list[str]]:
        from scratchworld_dist.kinds.tasks.report import build_report, render_html_body

        report = build_report([run_dir])
        return render_html_body(report), report.warnings

    def plots_html(self, rows: Sequence[JobRow]) -> str:
        from scratchworld_dist.kinds.tasks.report import plots_of

        return plots_html(plots_of(rows))

    def comparison_html(self, a: Path, b: Path) -> str:
        from scratchworld_dist.kinds.tasks.report import Selector, compare_runs, comparison_html

        return comparison_html(compare_runs(Selector(path=a), Selector(path=b), resamples=2000))

    def run_comparisons(self, rows: Sequence[JobRow]) -> list[RunComparison]:
        if len({row.mode for row in rows}) < 2:  # one model's gap needs both modes
            return []
        return [RunComparison("gap", "composite vs primitive", "reasoning-acting gap")]

    def run_comparison_html(self, run_dir: Path, name: str) -> str:
        from scratchworld_dist.kinds.tasks.report import Selector, compare_runs, comparison_html

        if name != "gap":
            raise ValueError(f"episode runs have no comparison {name!r}")
        left, right = Selector(path=run_dir, mode="composite"), Selector(path=run_dir, mode="primitive")
        return comparison_html(compare_runs(left, right, resamples=2000))


def selected_tasks(config: SweepConfig, trajectories: Path | None) -> tuple[Suite, list[TaskContent]]:
    """The config's suite and its selected tasks read under the config's evaluation conditions (``ConfigError``
    when the selection is empty); ``trajectories``: planned golden trajectories for tasks that ship none."""
    suite = load_suite(config.suite, task_list=config.tasks.task_list)
    tasks = suite.select(ids=config.tasks.ids or None, categories=config.tasks.categories or None)
    if not tasks:
        raise ConfigError(f"the task selection matches no task of {suite.name} ({suite.root})")
    conditions = (
        config.profile,
        config.clock,
        config.project_limits,
        config.render,
        trajectories,
        config.timing,
        config.evaluation_page,
    )
    return suite, [read_task(task, *conditions) for task in tasks]


def episode_settings(config: SweepConfig) -> EpisodeSweep:
    """The sweep's ``episodes:`` section (its defaults when the file has none)."""
    return config.section(TasksKind.name, EpisodeSweep)


def default_episode_clock(agent: type | None = None) -> EpisodeClock:
    """Virtual, for our suites and upstream clones alike: on upstream tasks the two clocks gave the same
    verdicts, test for test (docs/episodes-virtual-time.md), and only virtual ones repeat whatever the load.
    Real for an agent that acts on the wall clock (a person: ``real_time``)."""
    return EpisodeClock(mode="real" if getattr(agent, "real_time", False) else "virtual")


def offline_sources(config: SweepConfig) -> dict[tuple[str, Mode], list[JobItems]]:
    """Offline memory's items per (model name, mode), read from the previous run (empty for online memory)."""
    episodes = episode_settings(config)
    memory = episodes.memory
    if memory is None or memory.from_run is None:
        return {}
    if not memory.from_run.is_dir():
        raise ConfigError(f"episodes.memory.from_run: {memory.from_run} is not a run directory")
    names = [spec.name if spec is not None else NO_MODEL for spec in config.model_specs()]
    return {(name, mode): offline_source(memory.from_run, name, mode) for name in names for mode in episodes.modes}


TASKS = TasksKind()
"""The registered kind (entry point ``tasks``)."""
