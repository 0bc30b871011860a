"""Projects of create/star_shower (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Project, block, circle_costume


def _project() -> Project:
    project = Project(backdrop=None)
    project.sprite("Star", costume=circle_costume("star", 10, "#ffd500"), x=0, y=120)
    return project


def initial() -> Project:
    return _project()


def golden() -> Project:
    project = _project()
    star = project.sprites[0]
    star.script(
        block("event_whenflagclicked"),
        block("looks_hide"),
        block(
            "control_repeat",
            TIMES=5,
            SUBSTACK=[
                block("control_create_clone_of", CLONE_OPTION="_myself_"),
                block("control_wait", DURATION=0.2),
            ],
        ),
    )
    star.script(
        block("control_start_as_clone"),
        block("motion_gotoxy", X=block("operator_random", FROM=-200, TO=200), Y=170),
        block("looks_show"),
        block(
            "control_repeat_until",
            CONDITION=block("operator_lt", OPERAND1=block("motion_yposition"), OPERAND2=-160),
            SUBSTACK=[block("motion_changeyby", DY=-10)],
        ),
        block("control_delete_this_clone"),
    )
    return project
