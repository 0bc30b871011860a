"""Small projects built for tests."""

from __future__ import annotations

from scratchworld_dist.sb3 import Project, block, circle_costume


def counter_project(name: str = "Counter", target: int = 10) -> Project:
    """A sprite that counts a global variable up to ``target`` and says the result."""
    project = Project()
    project.stage.variable("count", 0)
    project.sprite(name, costume=circle_costume("dot", 10, "#36c")).script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="count", VALUE=0),
        block("control_repeat", TIMES=target, SUBSTACK=[block("data_changevariableby", VARIABLE="count", VALUE=1)]),
        block("looks_say", MESSAGE="done"),
    )
    return project
