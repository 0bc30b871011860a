"""Upstream's single-step drag benchmark, read in place from a ScratchWorld clone.

::

    CLONE/single_step_drag_benchmark/tasks/<id>.json   {id, category (T1|T2), instruction, init_project,
                                                        sprite?, evaluation_config{...}}
    CLONE/scratch-gui/static/<init_project>            the projects (T1_001.sb3 ...)

A task that cannot be read, or whose blocks are not its project's, is left out with a problem; a
task whose pre-actions cannot be mapped to a view is kept with ``view`` None and a problem.
"""

from __future__ import annotations

from math import gcd
from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from scratchworld_dist._errors import ProjectFormatError, validation_summary
from scratchworld_dist.kinds.drag.items._checks import UPSTREAM_FIELDS, block_problems, view_problems
from scratchworld_dist.kinds.drag.items._preactions import UpstreamWorkspaceState, view_from_upstream
from scratchworld_dist.kinds.drag.items._project import ProjectIndex, read_project_index
from scratchworld_dist.kinds.drag.items._suite import DragSuite, sort_drag_tasks
from scratchworld_dist.kinds.drag.items._task import DragTask, UpstreamAction, UpstreamDragReference
from scratchworld_dist.suites import SuiteKind, SuiteProblem, SuiteProblems, task_id_problem
from workers.contract import ConnectionKind, Point
from workers.kinds.drag import CONNECTIONS_OF, CanvasSource, DragSource, DragType, ExpectedConnection, FlyoutSource

TASKS_DIR = Path("single_step_drag_benchmark/tasks")
PROJECTS_DIR = Path("scratch-gui/static")


class UpstreamEvaluationConfig(BaseModel):
    """``evaluation_config``; keys we do not use (``pan_canvas_actions``' payloads, the reference's
    screen box) are ignored."""

    model_config = ConfigDict(extra="ignore")

    target_block_opcode: str = Field(min_length=1)
    target_block_id: str | None = None
    use_flyout: bool = False
    target_stack_tail_block_id: str | None = None
    reference_block_id: str = Field(min_length=1)
    reference_block_opcode: str = Field(min_length=1)
    connection_type: ConnectionKind
    target_input_name: str | None = None
    variable_name: str | None = None
    description: str = ""
    switch_sprite_actions: list[UpstreamAction] = Field(default_factory=list)
    locate_target_actions: list[UpstreamAction] = Field(default_factory=list)
    pan_canvas_actions: list[UpstreamAction] = Field(default_factory=list)
    workspace_state: UpstreamWorkspaceState | None = None
    drag_start_point: Point
    seed_point: Point | None = None
    first_valid_point: Point | None = None
    feasible_start_points: list[Point] = Field(default_factory=list)
    feasible_points: list[Point] = Field(default_factory=list)


class UpstreamDragFile(BaseModel):
    """single_step_drag_benchmark/tasks/<id>.json."""

    model_config = ConfigDict(extra="ignore")

    id: str
    category: DragType
    instruction: str = Field(min_length=1)
    init_project: str = Field(min_length=1)
    sprite: str | None = None
    """Upstream's note of the sprite its clicks select (lowercase, or "stage"); 10 tasks have it."""

    evaluation_config: UpstreamEvaluationConfig


class UpstreamDragLoader:
    """Loads a clone holding ``single_step_drag_benchmark/tasks/`` and ``scratch-gui/static/``."""

    kind: SuiteKind = "upstream"

    @staticmethod
    def handles(root: Path) -> bool:
        return (root / TASKS_DIR).is_dir() and (root / PROJECTS_DIR).is_dir()

    def load(self, root: Path) -> DragSuite:
        tasks: list[DragTask] = []
        problems: list[SuiteProblem] = []
        for path in sorted((root / TASKS_DIR).glob("*.json")):
            task, found = self._load_task(root, path)
            problems += found
            if task is not None:
                tasks.append(task)
        if not tasks and not problems:
            problems.append(SuiteProblem(path=root / TASKS_DIR, message=f"no task files under {TASKS_DIR}/"))
        return DragSuite(
            name=f"scratchworld-upstream-drag:{root.name}",
            kind="upstream",
            root=root,
            items=sort_drag_tasks(tasks),
            problems=tuple(problems),
        )

    def _load_task(self, root: Path, path: Path) -> tuple[DragTask | None, list[SuiteProblem]]:
        task_id = path.stem
        reader = SuiteProblems(root)
        bad_id = task_id_problem(task_id)
        if bad_id is not None:  # named by its folder: the name itself may hold a line break
            reader.add(path.parent, bad_id)
            return None, reader.of_item(None)
        file = reader.read_model(path, UpstreamDragFile)
        if file is None:
            return None, reader.of_item(task_id)
        config = file.evaluation_config
        if file.id != task_id:
            reader.add(path, f"id: {file.id!r} differs from the file name {task_id!r}")
        connection = _connection(config, file.category, reader, path)
        project_path, project = _project(root, file.init_project, reader, path)
        if connection is None or project is None or reader.items:
            return None, reader.of_item(task_id)
        # Upstream verifies by block id; its opcodes are labels, wrong in a few tasks. The
        # project's opcode is used and the difference reported.
        corrected: list[str] = []
        reference_opcode = _opcode(
            project, config.reference_block_id, config.reference_block_opcode, corrected, "reference"
        )
        source = _source(config, project, corrected, reader, path)
        if source is not None:
            for message in block_problems(
                project, source, config.reference_block_id, reference_opcode, UPSTREAM_FIELDS
            ):
                reader.add(path, message)
        if source is None or reader.items:
            return None, reader.of_item(task_id)

        view, unmapped = view_from_upstream(
            project,
            switch=config.switch_sprite_actions,
            locate=config.locate_target_actions,
            pan=config.pan_canvas_actions,
            workspace=config.workspace_state,
            sprite_hint=file.sprite,
        )
        if view is not None:
            unmapped = view_problems(project, view, source, config.reference_block_id, UPSTREAM_FIELDS)
        if unmapped:
            view = None
        try:
            task = DragTask(
                id=task_id,
                type=file.category,
                instruction=file.instruction,
                description=config.description,
                initial_project=project_path,
                source=source,
                reference_block_id=config.reference_block_id,
                reference_opcode=reference_opcode,
                connection=connection,
                view=view,
                upstream=_reference(config),
            )
        except ValidationError as exc:
            reader.add(path, validation_summary(exc))
            return None, reader.of_item(task_id)
        return task, [
            *(SuiteProblem(path=path, message=m, item_id=task_id, effect="corrected") for m in corrected),
            *(SuiteProblem(path=path, message=m, item_id=task_id, effect="no_view") for m in unmapped),
        ]


def _source(
    config: UpstreamEvaluationConfig, project: ProjectIndex, corrected: list[str], reader: SuiteProblems, path: Path
) -> DragSource | None:
    """A flyout source has no block id and ``use_flyout``; anything in between is ambiguous."""
    if config.use_flyout != (config.target_block_id is None):
        reader.add(
            path,
            "evaluation_config.use_flyout: must be true exactly when target_block_id is null "
            f"(use_flyout {str(config.use_flyout).lower()}, target_block_id {config.target_block_id!r})",
        )
        return None
    if config.target_block_id is None:
        return FlyoutSource(opcode=config.target_block_opcode)
    block_id = config.target_block_id
    return CanvasSource(
        block_id=block_id,
        opcode=_opcode(project, block_id, config.target_block_opcode, corrected, "target"),
        # When upstream names no tail it is the project's; when it does, block_problems compares the two.
        tail_block_id=config.target_stack_tail_block_id or project.stack_tail(block_id),
    )


def _opcode(project: ProjectIndex, block_id: str, opcode: str, corrected: list[str], role: str) -> str:
    """The project's opcode for ``block_id`` (noting where upstream's label differs), else upstream's."""
    found = project.opcode(block_id)
    if found is None or found == opcode:
        return opcode
    corrected.append(
        f"evaluation_config.{role}_block_opcode: {opcode!r}, but the project's block {block_id!r} is {found!r}; "
        "using the project's"
    )
    return found


def _connection(
    config: UpstreamEvaluationConfig, drag_type: DragType, reader: SuiteProblems, path: Path
) -> ExpectedConnection | None:
    kind = config.connection_type
    if kind not in CONNECTIONS_OF[drag_type]:
        allowed = ", ".join(CONNECTIONS_OF[drag_type])
        reader.add(path, f"evaluation_config.connection_type: {kind!r} is not a {drag_type} connection ({allowed})")
        return None
    if kind == "input" and not config.target_input_name:
        reader.add(path, "evaluation_config.target_input_name: connection_type 'input' needs the input's name")
        return None
    for key, value in (("target_input_name", config.target_input_name), ("variable_name", config.variable_name)):
        if kind != "input" and value is not None:
            reader.add(path, f"evaluation_config.{key}: only for connection_type 'input', not {kind!r}")
            return None
    try:
        return ExpectedConnection(kind=kind, input_name=config.target_input_name, variable_name=config.variable_name)
    except ValidationError as exc:
        reader.add(path, f"evaluation_config: {validation_summary(exc)}")
        return None


def _project(root: Path, name: str, reader: SuiteProblems, path: Path) -> tuple[Path, ProjectIndex | None]:
    project_path = root / PROJECTS_DIR / name
    named = Path(name)
    if named.is_absolute() or ".." in named.parts:  # a task file may not point at files elsewhere
        reader.add(path, f"init_project: {name!r} is outside {PROJECTS_DIR}/")
        return project_path, None
    if not project_path.is_file():
        reader.add(path, f"init_project: {name!r} does not exist at {project_path}")
        return project_path, None
    try:
        return project_path, read_project_index(project_path)
    except OSError as exc:
        reader.add(path, f"init_project: cannot read {project_path}: {exc.strerror or exc}")
    except ProjectFormatError as exc:
        reader.add(path, f"init_project: {project_path} is not a usable project: {exc}")
    return project_path, None


def _reference(config: UpstreamEvaluationConfig) -> UpstreamDragReference:
    return UpstreamDragReference(
        pre_actions=(*config.switch_sprite_actions, *config.locate_target_actions),
        drag_start_point=config.drag_start_point,
        feasible_start_points=tuple(config.feasible_start_points),
        feasible_points=tuple(config.feasible_points),
        start_grid_step=grid_step(config.feasible_start_points),
        end_grid_step=grid_step(config.feasible_points),
        seed_point=config.seed_point,
        first_valid_point=config.first_valid_point,
    )


def grid_step(points: list[Point]) -> int | None:
    """The largest step all ``points`` lie on from the first (None for fewer than two distinct)."""
    if not points:
        return None
    x0, y0 = points[0]
    step = 0
    for x, y in points[1:]:
        step = gcd(step, abs(x - x0), abs(y - y0))
    return step or None
