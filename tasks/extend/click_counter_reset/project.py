"""Projects of extend/click_counter_reset (rebuild with `python tasks/build_projects.py`)."""

from scratchworld_dist.sb3 import Project, block, circle_costume, variable


def initial() -> Project:
    """The working base: a click counter."""
    project = Project()
    project.stage.variable("clicks", 0)
    button = project.sprite("Button", costume=circle_costume("button", 40, "#ff6680"))
    button.script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="clicks", VALUE=0),
        block("looks_say", MESSAGE="Click me!"),
    )
    button.script(
        block("event_whenthisspriteclicked"),
        block("data_changevariableby", VARIABLE="clicks", VALUE=1),
        block("looks_say", MESSAGE=variable("clicks")),
    )
    return project


def golden() -> Project:
    project = initial()
    project.sprites[0].script(
        block("event_whenkeypressed", KEY_OPTION="r"),
        block("data_setvariableto", VARIABLE="clicks", VALUE=0),
        block("looks_say", MESSAGE="Reset!"),
    )
    return project
