"""Our own drag-suite format, read by ``load_drag_suite`` and written by ``write_drag_suite``.

::

    SUITE/drag-suite.json     {"format": "scratchworld_dist/drag/1", "name": ..., "tasks": ["<id>", ...]}
    SUITE/tasks/<id>.json     one DragTask; its initial_project is relative to SUITE
    SUITE/projects/<id>.sb3   the projects (written here; any path inside SUITE is accepted)

Unlike upstream's files, a task here is complete: it has a view, its blocks are its project's and
the view shows them, or it is left out with a problem. The manifest is written last, so a folder
whose writing was interrupted is not mistaken for a suite.
"""

from __future__ import annotations

from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from scratchworld_dist._errors import ProjectFormatError, SuiteError, validation_summary
from scratchworld_dist._files import MIB, read_file, write_atomic
from scratchworld_dist.kinds.drag.items._checks import OUR_FIELDS, block_problems, view_problems
from scratchworld_dist.kinds.drag.items._project import read_project_index
from scratchworld_dist.kinds.drag.items._suite import DragSuite
from scratchworld_dist.kinds.drag.items._task import DragTask
from scratchworld_dist.suites import SuiteKind, SuiteProblem, SuiteProblems, task_id_problem
from workers.contract import ProjectLimits

SUITE_FILE = "drag-suite.json"
FORMAT = "scratchworld_dist/drag/1"


class DragSuiteFile(BaseModel):
    """drag-suite.json."""

    model_config = ConfigDict(extra="forbid")

    format: Literal["scratchworld_dist/drag/1"]
    name: str = Field(min_length=1, pattern=r"^[^\x00-\x1f\x7f]*$")
    """Shown in every message and report: no line breaks or escape sequences."""

    tasks: list[str]
    """Task ids, in suite order; each is tasks/<id>.json."""


class NativeDragLoader:
    """Loads a folder holding ``drag-suite.json``."""

    kind: SuiteKind = "scratchworld_dist"

    @staticmethod
    def handles(root: Path) -> bool:
        return (root / SUITE_FILE).is_file()

    def load(self, root: Path) -> DragSuite:
        reader = SuiteProblems(root)
        manifest = reader.read_model(root / SUITE_FILE, DragSuiteFile)
        reader.raise_if_any()  # without the manifest there is no list of tasks to load
        assert manifest is not None
        tasks: list[DragTask] = []
        problems: list[SuiteProblem] = []
        seen: set[str] = set()
        for task_id in manifest.tasks:
            if task_id in seen:
                problems.append(SuiteProblem(path=root / SUITE_FILE, message=f"tasks: {task_id!r} is listed twice"))
                continue
            seen.add(task_id)
            task, found = self._load_task(root, task_id)
            problems += found
            if task is not None:
                tasks.append(task)
        for path in sorted((root / "tasks").glob("*.json")):
            if path.stem not in seen:
                problems.append(SuiteProblem(path=path, message=f"not listed in {SUITE_FILE}; not loaded"))
        return DragSuite(
            name=manifest.name, kind="scratchworld_dist", root=root, items=tuple(tasks), problems=tuple(problems)
        )

    def _load_task(self, root: Path, task_id: str) -> tuple[DragTask | None, list[SuiteProblem]]:
        reader = SuiteProblems(root)
        bad_id = task_id_problem(task_id)
        if bad_id is not None:
            reader.add(root / SUITE_FILE, f"tasks: {bad_id}")
            return None, reader.of_item(None)
        path = root / "tasks" / f"{task_id}.json"
        task = reader.read_model(path, DragTask)
        if task is None:
            return None, reader.of_item(task_id)
        if task.id != task_id:
            reader.add(path, f"id: {task.id!r} differs from the file name {task_id!r}")
        named = task.initial_project
        project_path = root / named
        project = None
        if named.is_absolute() or ".." in named.parts:
            reader.add(path, f"initial_project: {str(named)!r} is outside the suite folder")
        elif not project_path.is_file():
            reader.add(path, f"initial_project: {str(named)!r} does not exist at {project_path}")
        else:
            try:
                project = read_project_index(project_path)
            except OSError as exc:
                reader.add(path, f"initial_project: cannot read {project_path}: {exc.strerror or exc}")
            except ProjectFormatError as exc:
                reader.add(path, f"initial_project: {project_path} is not a usable project: {exc}")
        if task.view is None:
            reader.add(path, "view: required in a scratchworld_dist drag suite")
        if project is not None and not reader.items:
            for message in block_problems(
                project, task.source, task.reference_block_id, task.reference_opcode, OUR_FIELDS
            ):
                reader.add(path, message)
            if task.view is not None and not reader.items:
                for message in view_problems(project, task.view, task.source, task.reference_block_id, OUR_FIELDS):
                    reader.add(path, message)
        if reader.items:
            return None, reader.of_item(task_id)
        return task.model_copy(update={"initial_project": project_path}), []


def write_drag_suite(tasks: list[DragTask] | tuple[DragTask, ...], dest: Path, name: str) -> Path:
    """Write ``tasks`` as a suite of our format at ``dest`` (a new or empty folder), projects copied in.

    Raises ``SuiteError`` before writing anything if a task has no view, two tasks share an id or
    ``dest`` holds files; the suite reads back equal, but for project paths.
    """
    dest = Path(dest)
    try:
        manifest = DragSuiteFile(format=FORMAT, name=name, tasks=[t.id for t in tasks])
    except ValidationError as exc:
        raise SuiteError(f"cannot name a drag suite {name[:80]!r}: {validation_summary(exc)}", dest) from None
    if dest.exists() and (not dest.is_dir() or any(dest.iterdir())):
        raise SuiteError("refusing to write a drag suite into a folder that is not empty", dest)
    ids = [t.id for t in tasks]
    if len(set(ids)) != len(ids):
        raise SuiteError(f"two tasks share an id: {sorted({i for i in ids if ids.count(i) > 1})}", dest)
    for task in tasks:
        if task.view is None:
            raise SuiteError(f"task {task.id} has no view: a suite of ours holds only complete tasks", dest)
    limit = int(ProjectLimits().max_file_mb * MIB)
    (dest / "tasks").mkdir(parents=True, exist_ok=True)
    (dest / "projects").mkdir(exist_ok=True)
    for task in tasks:
        project = f"projects/{task.id}.sb3"
        try:
            data = read_file(task.initial_project, limit)
        except OSError as exc:
            raise SuiteError(
                f"cannot read the project of task {task.id}: {exc.strerror or exc}", task.initial_project
            ) from exc
        write_atomic(dest / project, data, sync=False)
        write_atomic(dest / "tasks" / f"{task.id}.json", task.dump(project).encode("utf-8"), sync=False)
    write_atomic(dest / SUITE_FILE, (manifest.model_dump_json(indent=2) + "\n").encode("utf-8"), sync=False)
    return dest
