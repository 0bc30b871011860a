"""A small project for drag-suite tests (Stage, Cat, Dog, Bird: ``SB3`` and its block ids, ``IDS``), and
the checks both layouts' tests share."""

from __future__ import annotations

from typing import Any

from scratchworld_dist.kinds.drag.items import DragSuite, DragTask
from scratchworld_dist.sb3 import Project, block, circle_costume


def _project() -> tuple[bytes, dict[tuple[str, str], str]]:
    """Stage, Cat, Dog, Bird with a few scripts; block ids by (target, opcode)."""
    project = Project()
    project.stage.script(block("event_whenflagclicked"), block("control_wait", DURATION=1))
    cat = project.sprite("Cat", costume=circle_costume("c", 10, "#f00"))
    cat.script(block("event_whenflagclicked"), block("motion_movesteps", STEPS=10))
    cat.script(block("motion_turnright", DEGREES=15), block("motion_turnleft", DEGREES=15))
    dog = project.sprite("Dog", costume=circle_costume("d", 10, "#0f0"))
    dog.script(block("event_whenflagclicked"), block("control_forever", SUBSTACK=[block("motion_sety", Y=0)]))
    project.sprite("Bird", costume=circle_costume("b", 10, "#00f")).script(block("event_whenflagclicked"))
    ids = {
        (target["name"], b["opcode"]): block_id
        for target in project.to_project_json()["targets"]
        for block_id, b in target["blocks"].items()
    }
    return project.to_sb3(), ids


SB3, IDS = _project()


def problems_of(suite: DragSuite, task_id: str) -> str:
    """The task's problems, each checked to be one line that names the task's file."""
    problems = [str(p) for p in suite.problems if p.item_id == task_id]
    assert problems
    for text in problems:
        assert "\n" not in text
        assert f"{task_id}.json: " in text
    return " | ".join(problems)


def without_project(task: DragTask) -> dict[str, Any]:
    return task.model_dump(exclude={"initial_project"})
