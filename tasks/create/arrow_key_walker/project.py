"""Projects of create/arrow_key_walker (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Project, block, circle_costume

# key -> (block, its slot, amount)
MOVES = {
    "right arrow": ("motion_changexby", "DX", 10),
    "left arrow": ("motion_changexby", "DX", -10),
    "up arrow": ("motion_changeyby", "DY", 10),
    "down arrow": ("motion_changeyby", "DY", -10),
}


def _project() -> Project:
    project = Project()
    project.sprite("Walker", costume=circle_costume("walker", 20, "#59c059"))
    return project


def initial() -> Project:
    return _project()


def golden() -> Project:
    project = _project()
    project.stage.variable("moves", 0)
    walker = project.sprites[0]
    walker.script(
        block("event_whenflagclicked"),
        block("motion_gotoxy", X=0, Y=0),
        block("data_setvariableto", VARIABLE="moves", VALUE=0),
    )
    for key, (opcode, slot, amount) in MOVES.items():
        walker.script(
            block("event_whenkeypressed", KEY_OPTION=key),
            block(opcode, **{slot: amount}),
            block("data_changevariableby", VARIABLE="moves", VALUE=1),
        )
    return project
