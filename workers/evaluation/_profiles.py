"""Evaluation profiles: the page conditions a verdict is made under, set explicitly and recorded.

Upstream evaluation scripts read the stage edges from the renderer's canvas, and ``go to
mouse-pointer`` yields NaN until a real mouse event reached the stage, so the same project can
pass or fail depending on the page. ``upstream`` reproduces the conditions behind the paper's
numbers (small stage, 240x180 canvas; mouse moved over the stage centre before the project
loads); ``native`` follows Scratch's own coordinates (large stage, 480x360). Window size and
device pixel ratio are pinned by the browser session and checked here.
"""

from __future__ import annotations

from workers.contract import EditorError, EvaluationProfile, ProfileConditions
from workers.editor import Editor

_STAGE_SIZE: dict[EvaluationProfile, str] = {"native": "large", "upstream": "small"}


STAGE_WIDTH, STAGE_HEIGHT = 480, 360
"""Scratch's stage in its own coordinates, whatever the canvas size."""


async def apply_profile(
    editor: Editor, profile: EvaluationProfile, mouse: tuple[float, float] | None = None
) -> ProfileConditions:
    """Put a fresh editor into the profile's conditions; raises ``EditorError`` if they do not hold.

    ``mouse`` (stage coordinates, a perturbation) is where a real mouse event puts the mouse instead
    of the profile's place (the stage centre for ``upstream``, nowhere for ``native``).
    """
    layout = await editor.set_stage_size(_STAGE_SIZE[profile])
    rect = layout.stage_rect
    if mouse is not None:
        x, y = mouse
        await editor.move_mouse(
            rect.x + (x / STAGE_WIDTH + 0.5) * rect.width, rect.y + (0.5 - y / STAGE_HEIGHT) * rect.height
        )
    elif profile == "upstream":
        await editor.move_mouse(rect.x + rect.width / 2, rect.y + rect.height / 2)
    status = await editor.status()
    conditions = ProfileConditions(
        profile=profile,
        stage_canvas=layout.canvas,
        device_pixel_ratio=status.device_pixel_ratio,
        mouse_known=status.mouse_known,
    )
    if conditions.device_pixel_ratio != 1 or (profile == "upstream" and not conditions.mouse_known):
        raise EditorError(f"the page does not meet the {profile} evaluation profile: {conditions}")
    return conditions
