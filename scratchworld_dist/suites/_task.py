"""A task and a suite of tasks, whatever layout they were loaded from."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Literal, get_args

from pydantic import BaseModel, ConfigDict, Field, TypeAdapter, ValidationError

from scratchworld_dist._errors import ConfigError, SuiteError, TaskNotFoundError
from scratchworld_dist._files import read_file, read_text
from scratchworld_dist.suites._generic import BaseSuite
from workers.contract import (
    CompositeAction,
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    EvaluationSpec,
    EvaluationTiming,
    calibrated_frame_lateness,
    editor_need,
    evaluation_seed,
    with_random_seed,
)

TaskCategory = Literal["create", "debug", "extend", "compute"]
CATEGORIES: tuple[TaskCategory, ...] = get_args(TaskCategory)

_TRAJECTORY = TypeAdapter(list[CompositeAction])

_TASK_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,127}$")


def task_id_problem(task_id: str) -> str | None:
    """Why ``task_id`` (a folder or file name) cannot name a task, or None.

    Ids appear in every message, table and result row: a newline, an escape sequence or markup in
    one would forge lines on a terminal or in a log, so an id is a plain name.
    """
    if _TASK_ID.match(task_id):
        return None
    return (
        f"task id {task_id[:200]!r} is not a plain name: use letters, digits, '.', '_' and '-' "
        "(at most 128, starting with a letter or digit)"
    )


class Task(BaseModel):
    """One benchmark task: what the agent is told, where it starts, and how it is judged."""

    model_config = ConfigDict(frozen=True)

    id: str
    """Unique within its suite (upstream: the task file's stem)."""

    category: TaskCategory
    """create, debug, extend or compute."""

    instruction: str
    """The only text the agent sees about the task."""

    description: str = ""
    """A note for people reading results; never shown to the agent."""

    initial_project: Path
    """The .sb3 the agent starts from."""

    golden_project: Path | None = None
    """A reference solution, when the suite has one."""

    golden_trajectory: Path | None = None
    """Composite actions (JSON list of ``{"api", "args"}``) that turn the initial project into a solution."""

    evaluation_script: Path
    """CommonJS module exporting ``async (vm, config, cleanup) => result``."""

    helper_script: Path | None = None
    """The suite's helper module, installed as ``helper_global`` before the script runs."""

    helper_global: str = "EvaluationUtils"
    """Global name of the helper module's exports."""

    timeout_s: float = Field(gt=0)
    """Hard limit for one evaluation of this task."""

    default_profile: EvaluationProfile = "native"
    """Evaluation profile unless the user picks one (upstream suites: ``upstream``)."""

    default_clock: EvaluationClock = "real"
    """Evaluation clock unless the user picks one (our suite: ``virtual``, checked equivalent by tests)."""

    def evaluation_spec(
        self,
        profile: EvaluationProfile | None = None,
        clock: EvaluationClock | None = None,
        render: EvaluationRender | None = None,
        timing: EvaluationTiming | None = None,
        *,
        page: EvaluationPage | None = None,
        seed: int | None = None,
    ) -> EvaluationSpec:
        """The script and helper sources, read now, ready to send to a worker (render: on demand by default;
        timing: see ``default_timing``; page: bare, unless the script needs the editor). With ``seed`` (a
        sweep seed), ``Math.random`` draws as in this task's jobs at that seed; without, the worker seeds it."""
        profile = profile or self.default_profile
        clock = clock or self.default_clock
        timing = timing or default_timing(profile, clock)
        if timing == "calibrated" and clock != "virtual":
            raise ConfigError("calibrated frame timing needs the virtual clock (the real clock has its own)")
        spec = EvaluationSpec(
            profile=profile,
            clock=clock,
            render=render or "on_demand",
            page=page or "bare",
            timing=timing,
            frame_lateness=calibrated_frame_lateness() if timing == "calibrated" else None,
            script_name=self.evaluation_script.name,
            script_source=_read_text(self.evaluation_script),
            helper_name=self.helper_script.name if self.helper_script else None,
            helper_source=_read_text(self.helper_script) if self.helper_script else None,
            helper_global=self.helper_global,
            timeout_s=self.timeout_s,
        )
        return spec if seed is None else with_random_seed(spec, evaluation_seed(self.id, seed))

    def editor_need(self) -> str | None:
        """What in the task's scripts only the editor page has (its evaluations then run there), or None."""
        helper = _read_text(self.helper_script) if self.helper_script else None
        return editor_need(_read_text(self.evaluation_script), helper)

    def trajectory(self) -> list[CompositeAction] | None:
        """The golden trajectory, read and checked now."""
        if self.golden_trajectory is None:
            return None
        return read_trajectory(self.golden_trajectory)


def default_timing(profile: EvaluationProfile, clock: EvaluationClock) -> EvaluationTiming:
    """``calibrated`` for upstream suites in virtual time (their goldens are tuned to Chromium's real frame
    rate), ``ideal`` otherwise (our suite's verdicts were checked equivalent in ideal time)."""
    return "calibrated" if profile == "upstream" and clock == "virtual" else "ideal"


def read_trajectory(path: Path) -> list[CompositeAction]:
    """A trajectory file: a JSON list of ``{"api": ..., "args": {...}}`` objects."""
    try:
        return _TRAJECTORY.validate_json(read_file(path))
    except OSError as exc:
        raise SuiteError(f"cannot read the trajectory: {exc}", path) from exc
    except ValidationError as exc:
        problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in exc.errors()[:5])
        raise SuiteError(f'not a list of {{"api", "args"}} actions: {problems}', path) from None


def _read_text(path: Path) -> str:
    try:
        return read_text(path)
    except (OSError, UnicodeDecodeError) as exc:
        raise SuiteError(f"cannot read the script: {exc}", path) from exc


class Suite(BaseSuite[Task]):
    """The tasks found in one folder, in a stable order (category, then id); any problem fails the load."""

    @property
    def tasks(self) -> tuple[Task, ...]:
        return self.items

    def task(self, task_id: str) -> Task:
        for task in self.tasks:
            if task.id == task_id:
                return task
        raise TaskNotFoundError(f"no task {task_id!r} in suite {self.name} ({self.root})")

    def select(self, ids: list[str] | None = None, categories: list[str] | None = None) -> list[Task]:
        """Tasks by id (every id must exist) and/or category, in suite order."""
        for category in categories or []:
            if category not in CATEGORIES:
                raise SuiteError(f"unknown category {category!r}; categories are {', '.join(CATEGORIES)}")
        chosen = {self.task(task_id).id for task_id in ids} if ids else None
        return [
            t for t in self.tasks if (chosen is None or t.id in chosen) and (not categories or t.category in categories)
        ]


def sort_tasks(tasks: list[Task]) -> tuple[Task, ...]:
    return tuple(sorted(tasks, key=lambda t: (CATEGORIES.index(t.category), t.id)))
