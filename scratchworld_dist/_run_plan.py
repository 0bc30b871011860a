"""Planning a sweep: its config resolved against its suite (tasks, drag tasks or perception items) and a
harness into the full job matrix, with each item's content read once."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel
from rich.console import Console

from scratchworld_dist._errors import ConfigError
from scratchworld_dist.drag import DragTask, load_drag_suite
from scratchworld_dist.memory import JobItems, offline_source, source_digest
from scratchworld_dist.results import SuiteInfo
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import NO_MODEL, JobSpec, SweepConfig, TaskContent, plan_jobs, read_task, suite_hash
from scratchworld_dist.sweep._drag_plan import DragContent, plan_drag_jobs, read_drag_task
from scratchworld_dist.sweep._perception_plan import (
    PerceptionContent,
    plan_perception_jobs,
    select_perception_items,
)
from scratchworld_dist.sweep._selection import present_suites, wanted_ids
from workers.agent_api import agent_class, agent_code, agent_params, extra_models
from workers.contract import EpisodeClock, HarnessFingerprint, Mode
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint


class RunPlan(BaseModel):
    """A sweep resolved against its suite and this harness: the tasks' contents and the full job matrix."""

    config: SweepConfig
    harness: HarnessFingerprint
    suite: SuiteInfo
    contents: list[TaskContent] | list[DragContent] | list[PerceptionContent]
    jobs: list[JobSpec]
    memory_sources: dict[tuple[str, Mode], list[JobItems]] = {}
    """Offline memory: the previous run's proposals per (model name, mode)."""


def plan_run(config: SweepConfig, harness: HarnessFingerprint | None = None) -> RunPlan:
    """The sweep's jobs under ``harness`` (default: this machine's code, editor and browser)."""
    harness = kind_fingerprint(harness or harness_fingerprint(), config.benchmark)  # the core + this kind's code
    if config.benchmark == "drag":
        return plan_drag_run(config, harness)
    if config.benchmark == "perception":
        return plan_perception_run(config, harness)
    suite = load_suite(config.suite, task_list=config.tasks.task_list)
    tasks = suite.select(ids=config.tasks.ids or None, categories=config.tasks.categories or None)
    if not tasks:
        raise ConfigError(f"the task selection matches no task of {suite.name} ({suite.root})")
    contents = [
        read_task(
            task,
            config.profile,
            config.clock,
            config.project_limits,
            config.render,
            config.oracle_trajectories,
            config.timing,
        )
        for task in tasks
    ]
    unknown = sorted(set(config.synthetic.tasks or []) - {t.id for t in tasks}) if config.synthetic else []
    if unknown:
        raise ConfigError(f"synthetic.tasks names task(s) not in the selection: {', '.join(unknown)}")
    info = SuiteInfo(
        name=suite.name,
        kind=suite.kind,
        root=str(suite.root),
        hash=suite_hash(contents),
        tasks=len(tasks),
    )
    found = agent_class(config.agent.name)
    helpers = extra_models(agent_params(found, config.agent))
    sources = offline_sources(config) if config.memory is not None else {}
    jobs = list(
        plan_jobs(
            config.model_specs(),
            config.modes,
            config.agent,
            contents,
            config.seeds,
            config.max_steps,
            config.primitive,
            config.llm,
            config.project_limits,
            harness.digest,
            config.synthetic,
            agent_code(found),
            helpers,
            config.memory,
            {stream: source_digest(entries) for stream, entries in sources.items()},
            config.episode_clock or default_episode_clock(suite.kind),
            config.model_cache,
        )
    )
    return RunPlan(config=config, harness=harness, suite=info, contents=contents, jobs=jobs, memory_sources=sources)


def plan_drag_run(config: SweepConfig, harness: HarnessFingerprint, notice: Any = None) -> RunPlan:
    """The drag benchmark's jobs: the suite's tasks (and those of each optional suite that is present)
    with a view, selected by ``tasks.ids`` and ``drag.types``; a task without a view is left out, named."""
    say = notice or Console(stderr=True, soft_wrap=True).print
    suites = present_suites(
        config.suite,
        config.drag.optional_suites,
        load_drag_suite,
        lambda message: say(message, markup=False),
        benchmark="drag",
        item="task",
    )
    tasks: list[DragTask] = []
    for suite in suites:
        for task in suite.tasks:
            if task.view is None:
                say(f"drag: {suite.name} {task.id} has no usable view and is left out", markup=False)
                continue
            tasks.append(task)
    wanted = wanted_ids([task.id for task in tasks], config.tasks.ids, benchmark="drag", item="task")
    tasks = [
        t for t in tasks if (not wanted or t.id in wanted) and (not config.drag.types or t.type in config.drag.types)
    ]
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
    jobs = list(
        plan_drag_jobs(
            config.model_specs(),
            config.drag.settings,
            config.drag_agents(),
            contents,
            config.seeds,
            element_list=config.drag.element_list,
            observation=config.primitive,
            llm=config.llm,
            project_limits=config.project_limits,
            harness=harness.digest,
            model_cache=config.model_cache,
        )
    )
    return RunPlan(config=config, harness=harness, suite=info, contents=contents, jobs=jobs)


def plan_perception_run(config: SweepConfig, harness: HarnessFingerprint, notice: Any = None) -> RunPlan:
    """The perception benchmark's jobs: the items of the suite (and of each optional suite that is present),
    selected by ``tasks.ids`` and ``perception.kinds``."""
    say = notice or Console(stderr=True, soft_wrap=True).print
    perception = config.perception
    selection = select_perception_items(
        config.suite,
        perception.optional_suites,
        config.tasks.ids,
        perception.kinds,
        lambda message: say(message, markup=False),
    )
    contents = selection.contents
    info = SuiteInfo(
        name=selection.name, kind=selection.kind, root=str(selection.root), hash=suite_hash(contents),
        tasks=len(contents),
    )  # fmt: skip
    jobs = plan_perception_jobs(
        config.model_specs(),
        config.perception_agents(),
        contents,
        config.seeds,
        llm=config.llm,
        harness=harness.digest,
        model_cache=config.model_cache,
    )
    return RunPlan(config=config, harness=harness, suite=info, contents=contents, jobs=list(jobs))


def default_episode_clock(suite_kind: str) -> EpisodeClock:
    """Virtual for our suites; real for upstream clones until the two are compared on them."""
    return EpisodeClock(mode="real" if suite_kind == "upstream" else "virtual")


def offline_sources(config: SweepConfig) -> dict[tuple[str, Mode], list[JobItems]]:
    """Offline memory's items per (model name, mode), read from the previous run (empty for online memory)."""
    memory = config.memory
    if memory is None or memory.from_run is None:
        return {}
    if not memory.from_run.is_dir():
        raise ConfigError(f"memory.from_run: {memory.from_run} is not a run directory")
    names = [spec.name if spec is not None else NO_MODEL for spec in config.model_specs()]
    return {(name, mode): offline_source(memory.from_run, name, mode) for name in names for mode in config.modes}
