"""Our own suite layout (documented in tasks/README.md).

::

    SUITE/suite.json                      {"format": "scratchworld_dist/1", "name": ..., "helper": ...}
    SUITE/<helper>.js                     helper module shared by every script
    SUITE/<category>/<task_id>/task.json  {"instruction": ..., "description": ..., "timeout_s": ...}
    SUITE/<category>/<task_id>/initial.sb3
    SUITE/<category>/<task_id>/golden.sb3   (optional)
    SUITE/<category>/<task_id>/evaluate.js
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field

from scratchworld_dist.suites._generic import SuiteKind
from scratchworld_dist.suites._problems import SuiteProblems
from scratchworld_dist.suites._task import CATEGORIES, Suite, Task, sort_tasks, task_id_problem

SUITE_FILE = "suite.json"
TASK_FILE = "task.json"


class SuiteFile(BaseModel):
    """suite.json."""

    model_config = ConfigDict(extra="forbid")

    format: Literal["scratchworld_dist/1"]
    name: str = Field(min_length=1, pattern=r"^[^\x00-\x1f\x7f]*$")
    """Shown in every message and report: no line breaks or escape sequences."""

    helper: str | None = None
    helper_global: str = Field(default="EvaluationUtils", pattern=r"^[A-Za-z_$][\w$]*$")


class TaskFile(BaseModel):
    """<category>/<task_id>/task.json."""

    model_config = ConfigDict(extra="forbid")

    instruction: str = Field(min_length=1)
    description: str = ""
    timeout_s: float = Field(default=60.0, gt=0, le=3600)


class NativeSuiteLoader:
    """Loads a folder holding ``suite.json``; ``task_list`` (an upstream-clone feature) is refused."""

    kind: SuiteKind = "scratchworld_dist"

    def __init__(self, task_list: str | None = None) -> None:
        self.task_list = task_list

    @staticmethod
    def handles(root: Path) -> bool:
        return (root / SUITE_FILE).is_file()

    def load(self, root: Path) -> Suite:
        problems = SuiteProblems(root)
        if self.task_list is not None:
            problems.add(root / SUITE_FILE, "task lists are an upstream-clone feature; select tasks by id instead")
        suite_file = problems.read_model(root / SUITE_FILE, SuiteFile)
        problems.raise_if_any()
        assert suite_file is not None

        helper = root / suite_file.helper if suite_file.helper else None
        if helper is not None and not helper.is_file():
            problems.add(root / SUITE_FILE, f"helper {suite_file.helper!r} does not exist at {helper}")
        for entry in sorted(root.iterdir()):
            if entry.is_dir() and not entry.name.startswith((".", "_")) and entry.name not in CATEGORIES:
                problems.add(entry, f"unknown category folder {entry.name!r}; categories are {', '.join(CATEGORIES)}")

        tasks: list[Task] = []
        for category in CATEGORIES:
            folder = root / category
            if not folder.is_dir():
                continue
            for task_dir in sorted(p for p in folder.iterdir() if p.is_dir()):
                task = self._load_task(task_dir, category, suite_file, helper, problems)
                if task is not None:
                    tasks.append(task)
        if not tasks and not problems.items:
            problems.add(root, "the suite has no tasks")
        problems.raise_if_any()
        return Suite(name=suite_file.name, kind="scratchworld_dist", root=root, items=sort_tasks(tasks))

    def _load_task(
        self, task_dir: Path, category: str, suite_file: SuiteFile, helper: Path | None, problems: SuiteProblems
    ) -> Task | None:
        before = len(problems.items)
        bad_id = task_id_problem(task_dir.name)
        if bad_id is not None:  # named by its folder: the name itself may hold a line break
            problems.add(task_dir.parent, bad_id)
            return None
        task_file = problems.read_model(task_dir / TASK_FILE, TaskFile)
        for required in ("initial.sb3", "evaluate.js"):
            if not (task_dir / required).is_file():
                problems.add(task_dir / required, "missing")
        if len(problems.items) > before or task_file is None:
            return None
        golden = task_dir / "golden.sb3"
        trajectory = task_dir / "golden_trajectory.json"
        return Task(
            id=task_dir.name,
            category=category,  # type: ignore[arg-type]
            instruction=task_file.instruction,
            description=task_file.description,
            initial_project=task_dir / "initial.sb3",
            golden_project=golden if golden.is_file() else None,
            golden_trajectory=trajectory if trajectory.is_file() else None,
            evaluation_script=task_dir / "evaluate.js",
            helper_script=helper,
            helper_global=suite_file.helper_global,
            timeout_s=task_file.timeout_s,
            default_clock="virtual",
        )
