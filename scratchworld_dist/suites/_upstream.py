"""A clone of the upstream ScratchWorld repository, read in place.

::

    CLONE/tasks/<category>/<name>.json           task files (only `instruction` reaches the agent)
    CLONE/tasks/<list>.json                      task lists {"<category>": ["<name>.json", ...]}
    CLONE/scratch-gui/static/<initial_project>   initial projects; goldens are <name>_golden.sb3,
                                                 debug tasks share <starter>_golden.sb3
    CLONE/scratch-bench-api/api/evaluation_scripts/<name>.js  plus evaluation_utils.js

The task file's ``evaluation.timeout`` is informative upstream (scripts carry their own case
timeouts under a fixed 120 s limit), so every task gets that 120 s limit here too.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from scratchworld_dist.suites._generic import SuiteKind
from scratchworld_dist.suites._problems import SuiteProblems
from scratchworld_dist.suites._task import CATEGORIES, Suite, Task, sort_tasks, task_id_problem

UPSTREAM_TIMEOUT_S = 120.0
SCRIPTS_DIR = Path("scratch-bench-api/api/evaluation_scripts")
PROJECTS_DIR = Path("scratch-gui/static")
HELPER_FILE = "evaluation_utils.js"


class UpstreamTaskFile(BaseModel):
    """tasks/<category>/<name>.json; keys we do not use are ignored."""

    model_config = ConfigDict(extra="ignore")

    name: str = ""
    description: str = ""
    type: str
    instruction: str = Field(min_length=1)
    initial_project: str = Field(min_length=1)


def find_golden(projects: Path, task_id: str, category: str) -> Path | None:
    """``<name>_golden.sb3``; a debug task falls back to its starter's golden, the longest
    ``_``-separated prefix of its name that has one (``pong_starter_x_error`` -> ``pong_starter``)."""
    parts = task_id.split("_")
    stop = 0 if category == "debug" else len(parts) - 1
    for end in range(len(parts), stop, -1):
        candidate = projects / f"{'_'.join(parts[:end])}_golden.sb3"
        if candidate.is_file():
            return candidate
    return None


class UpstreamSuiteLoader:
    """Loads a ScratchWorld clone (its ``tasks/`` and ``scratch-gui/static/`` folders).

    ``task_list`` (a file, or a name under ``tasks/``) picks the tasks it lists. ``require_scripts=False``
    loads tasks whose evaluation scripts are absent (their paths are kept): for what needs only the
    projects, such as planning oracle trajectories.
    """

    kind: SuiteKind = "upstream"

    def __init__(self, require_scripts: bool = True, task_list: str | None = None) -> None:
        self.require_scripts = require_scripts
        self.task_list = task_list

    @staticmethod
    def handles(root: Path) -> bool:
        return (root / "tasks").is_dir() and (root / PROJECTS_DIR).is_dir()

    def load(self, root: Path) -> Suite:
        task_list = self.task_list
        problems = SuiteProblems(root)
        scripts = root / SCRIPTS_DIR
        helper = scripts / HELPER_FILE
        wanted = self._task_list(root, task_list, problems) if task_list else None

        tasks: list[Task] = []
        for category in CATEGORIES:
            folder = root / "tasks" / category
            if not folder.is_dir():
                continue
            for path in sorted(folder.glob("*.json")):
                if wanted is not None and path.name not in wanted.get(category, ()):
                    continue
                task = self._load_task(root, path, category, helper, problems)
                if task is not None:
                    tasks.append(task)
        if wanted is not None:
            for category, names in wanted.items():
                for name in names:
                    if not (root / "tasks" / category / name).is_file():
                        problems.add(root / "tasks" / category / name, f"listed in {task_list} but missing")
        if tasks and self.require_scripts and not helper.is_file():
            problems.add(helper, "missing: upstream scripts need the helper module evaluation_utils.js")
        if not tasks and not problems.items:
            problems.add(root / "tasks", "no task files under tasks/<category>/")
        problems.raise_if_any()
        return Suite(name=f"scratchworld-upstream:{root.name}", kind="upstream", root=root, items=sort_tasks(tasks))

    def _task_list(self, root: Path, task_list: str, problems: SuiteProblems) -> dict[str, list[str]]:
        path = Path(task_list)
        if not path.is_file():
            path = root / "tasks" / (task_list if task_list.endswith(".json") else f"{task_list}.json")
        data: Any = problems.read_json(path)
        if data is None:
            problems.raise_if_any()
        if not isinstance(data, dict) or not all(
            isinstance(names, list) and all(isinstance(n, str) for n in names) for names in data.values()
        ):
            problems.add(path, 'a task list must look like {"<category>": ["<name>.json", ...]}')
            problems.raise_if_any()
        for category in data:
            if category not in CATEGORIES:
                problems.add(path, f"unknown category {category!r}; categories are {', '.join(CATEGORIES)}")
        problems.raise_if_any()
        return data

    def _load_task(
        self, root: Path, path: Path, folder_category: str, helper: Path, problems: SuiteProblems
    ) -> Task | None:
        bad_id = task_id_problem(path.stem)
        if bad_id is not None:  # named by its folder: the name itself may hold a line break
            problems.add(path.parent, bad_id)
            return None
        task_file = problems.read_model(path, UpstreamTaskFile)
        if task_file is None:
            return None
        if task_file.type not in CATEGORIES:
            problems.add(path, f"unknown category {task_file.type!r}; categories are {', '.join(CATEGORIES)}")
            return None
        if task_file.type != folder_category:
            problems.add(path, f"declares type {task_file.type!r} but lives in tasks/{folder_category}/")
            return None
        task_id = path.stem
        initial = root / PROJECTS_DIR / task_file.initial_project
        script = root / SCRIPTS_DIR / f"{task_id}.js"
        ok = True
        named = Path(task_file.initial_project)
        if named.is_absolute() or ".." in named.parts:  # a task file may not point at files elsewhere
            problems.add(path, f"initial_project {task_file.initial_project!r} is outside {PROJECTS_DIR}/")
            ok = False
        elif not initial.is_file():
            problems.add(path, f"initial_project {task_file.initial_project!r} does not exist at {initial}")
            ok = False
        if self.require_scripts and not script.is_file():
            problems.add(path, f"evaluation script missing: {script}")
            ok = False
        if not ok:
            return None
        return Task(
            id=task_id,
            category=task_file.type,  # type: ignore[arg-type]
            instruction=task_file.instruction,
            description=task_file.description,
            initial_project=initial,
            golden_project=find_golden(root / PROJECTS_DIR, task_id, task_file.type),
            evaluation_script=script,
            helper_script=helper,
            helper_global="EvaluationUtils",
            timeout_s=UPSTREAM_TIMEOUT_S,
            default_profile="upstream",
            # Virtual: upstream's own scripts give the real clock's verdicts on every test the suite's known
            # stability calls stable, ~30x faster and whatever the machine's load (docs/evaluation.md).
            default_clock="virtual",
        )
