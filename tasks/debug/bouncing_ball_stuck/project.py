"""Projects of debug/bouncing_ball_stuck (rebuild with `python tasks/build_projects.py`).

The ball should fly diagonally and bounce off every edge; in the initial project the
"if on edge, bounce" block sits before the forever loop, so it runs once and the ball ends up
stuck in the top-right corner.
"""

from scratchworld_dist.sb3 import Project, backdrop_costume, block, circle_costume


def _project() -> Project:
    project = Project(backdrop=backdrop_costume("court", "#dff5e1"))
    project.sprite("Ball", costume=circle_costume("ball", 15, "#f5a623"))
    return project


def _reset() -> list:
    return [
        block("event_whenflagclicked"),
        block("motion_gotoxy", X=0, Y=0),
        block("motion_pointindirection", DIRECTION=45),
    ]


def initial() -> Project:
    project = _project()
    project.sprites[0].script(
        *_reset(),
        block("motion_ifonedgebounce"),
        block("control_forever", SUBSTACK=[block("motion_movesteps", STEPS=20)]),
    )
    return project


def golden() -> Project:
    project = _project()
    project.sprites[0].script(
        *_reset(),
        block(
            "control_forever",
            SUBSTACK=[block("motion_movesteps", STEPS=20), block("motion_ifonedgebounce")],
        ),
    )
    return project
