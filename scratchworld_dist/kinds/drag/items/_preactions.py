"""Turning upstream's pixel pre-actions into a ``DragView``.

Upstream sets a task's view up with page clicks (``switch_sprite_actions``, then
``locate_target_actions``: a sprite tile or the Stage selector, a category button, a wheel over
the flyout) and one ``custom_js`` that shifts the workspace's SVG transform, whose result the
task records as ``workspace_state``. Here each click is matched against upstream's layout
(``_layout``) and the project's sprites, and the transform becomes scroll and scale.

Order matters and is taken as upstream's runner has it: target switch, category, then the
workspace transform, the only order in which the recorded transform survives (selecting another
target restores that target's own scroll). Every action that cannot be read with certainty
gives a message and no view: a wrong view would silently change what the model is shown.
"""

from __future__ import annotations

import hashlib
import math
import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from pydantic import BaseModel, ConfigDict, Field

from scratchworld_dist.kinds.drag.items._layout import category_at, on_flyout, on_stage_selector, sprite_tile_at
from scratchworld_dist.kinds.drag.items._project import ProjectIndex, ProjectTarget
from scratchworld_dist.kinds.drag.items._task import UpstreamAction
from workers.contract import DragView, PaletteCategory

PAN_SCRIPT_SHA256 = "2b5ed1cba5d4e12b411d9db8859915bcdf4f07005335dcd4e1b104fba01faecc"
"""The one ``custom_js`` all 60 upstream tasks run: it adds ``payload.dx/dy`` to the workspace
canvas's ``translate``, keeps its scale, and sets ``ws.scrollX/Y = -translate / scale``. Its result
is the task's ``workspace_state``; any other script could set anything, so it is not trusted."""

DEFAULT_WHEEL = 100
"""Upstream's ``scroll`` amount when the action gives none."""

_TRANSFORM = re.compile(r"^\s*translate\(\s*([^,\s]+)\s*,\s*([^)\s]+)\s*\)\s*scale\(\s*([^)\s]+)\s*\)\s*$")


class UpstreamWorkspaceState(BaseModel):
    """``evaluation_config.workspace_state``: the main workspace's transform after upstream's pan."""

    model_config = ConfigDict(frozen=True, extra="ignore")

    tx: float
    ty: float
    scale: float = Field(gt=0)
    scrollX: float  # noqa: N815 (upstream's key)
    scrollY: float  # noqa: N815
    transform: str | None = None


@dataclass
class _Reading:
    """The view as the actions so far have set it, and what could not be read."""

    target: ProjectTarget | None
    category: PaletteCategory | None = None
    flyout_scroll: float = 0
    problems: list[str] = field(default_factory=list)

    def fail(self, message: str) -> None:
        self.problems.append(message)


def view_from_upstream(
    project: ProjectIndex,
    *,
    switch: Sequence[UpstreamAction],
    locate: Sequence[UpstreamAction],
    pan: Sequence[UpstreamAction],
    workspace: UpstreamWorkspaceState | None,
    sprite_hint: str | None,
) -> tuple[DragView | None, list[str]]:
    """The view upstream's pre-actions set up, or None and why (one line each, naming the field)."""
    reading = _Reading(target=project.default_target())
    if reading.target is None:
        reading.fail("init_project: the project has no targets")
    for index, action in enumerate(switch):
        _apply(reading, project, action, f"evaluation_config.switch_sprite_actions[{index}]")
    for index, action in enumerate(locate):
        _apply(reading, project, action, f"evaluation_config.locate_target_actions[{index}]")
    for index, action in enumerate(pan):
        _check_pan(reading, action, f"evaluation_config.pan_canvas_actions[{index}]")
    _check_workspace(reading, workspace)
    if sprite_hint is not None and reading.target is not None and not _names(reading.target, sprite_hint):
        reading.fail(f"sprite: upstream names {sprite_hint!r} but its clicks select {reading.target.label}")
    if reading.problems or reading.target is None or workspace is None:
        return None, reading.problems
    view = DragView(
        sprite=None if reading.target.is_stage else reading.target.name,
        category=reading.category,
        flyout_scroll=reading.flyout_scroll,
        scroll_x=workspace.scrollX,
        scroll_y=workspace.scrollY,
        scale=workspace.scale,
    )
    return view, []


def _apply(reading: _Reading, project: ProjectIndex, action: UpstreamAction, where: str) -> None:
    point = _point(action)
    if action.api == "click" and point is not None and action.args.get("button", "left") == "left":
        _click(reading, project, point, where)
    elif action.api == "scroll" and point is not None:
        _wheel(reading, action, point, where)
    elif action.api in ("click", "scroll"):
        reading.fail(f"{where}: a {action.api} needs numeric x and y (and a left button) to be read")
    else:
        reading.fail(f"{where}: {action.api!r} is not a click or a scroll; what it does to the view is unknown")


def _click(reading: _Reading, project: ProjectIndex, point: tuple[float, float], where: str) -> None:
    x, y = point
    category = category_at(x, y)
    if category is not None:
        reading.category, reading.flyout_scroll = category, 0
        return
    tile = sprite_tile_at(x, y)
    if tile is None and not on_stage_selector(x, y):
        reading.fail(f"{where}: click ({x:g}, {y:g}) is on no category button, sprite tile or Stage selector")
        return
    if reading.category is not None:
        reading.fail(f"{where}: a target switch after a category click leaves the palette's scroll unknown")
        return
    if tile is None:
        reading.target = project.stage
        if reading.target is None:
            reading.fail(f"{where}: click ({x:g}, {y:g}) selects the Stage but the project has none")
    elif tile >= len(project.sprites):
        count = len(project.sprites)
        reading.fail(f"{where}: click ({x:g}, {y:g}) is on sprite tile {tile + 1}, the project has {count} sprite(s)")
    else:
        reading.target = project.sprites[tile]


def _wheel(reading: _Reading, action: UpstreamAction, point: tuple[float, float], where: str) -> None:
    x, y = point
    direction = action.args.get("direction", "down")
    amount = action.args.get("amount", DEFAULT_WHEEL)
    if not on_flyout(x, y):
        reading.fail(f"{where}: scroll at ({x:g}, {y:g}) is not over the flyout")
    elif reading.category is None:
        reading.fail(f"{where}: a flyout scroll before any category click scrolls from an unknown place")
    elif direction not in ("down", "up") or not _number(amount) or amount < 0:
        reading.fail(f"{where}: scroll needs direction 'down' or 'up' and a non-negative amount")
    else:
        reading.flyout_scroll = max(0.0, reading.flyout_scroll + (amount if direction == "down" else -amount))


def _check_pan(reading: _Reading, action: UpstreamAction, where: str) -> None:
    script = action.args.get("fn")
    if action.api != "custom_js" or not isinstance(script, str):
        reading.fail(f"{where}: expected upstream's custom_js pan, got {action.api!r}")
    elif hashlib.sha256(script.encode("utf-8")).hexdigest() != PAN_SCRIPT_SHA256:
        reading.fail(f"{where}: custom_js is not upstream's pan script; what it sets is unknown")


def _check_workspace(reading: _Reading, workspace: UpstreamWorkspaceState | None) -> None:
    """``scrollX/Y`` must be what the pan script derives from the transform, or the state is not one."""
    where = "evaluation_config.workspace_state"
    if workspace is None:
        reading.fail(f"{where}: missing, so the workspace's scroll and scale are unknown")
        return
    for key, scroll, translate in (
        ("scrollX", workspace.scrollX, workspace.tx),
        ("scrollY", workspace.scrollY, workspace.ty),
    ):
        if not math.isclose(scroll, -translate / workspace.scale, rel_tol=1e-9, abs_tol=1e-6):
            reading.fail(f"{where}: {key} {scroll:g} is not -translate/scale ({-translate / workspace.scale:g})")
    if workspace.transform is not None:
        match = _TRANSFORM.match(workspace.transform)
        parsed = [_float(v) for v in match.groups()] if match else []
        expected = [workspace.tx, workspace.ty, workspace.scale]
        if len(parsed) != 3 or not all(
            p is not None and math.isclose(p, e, abs_tol=1e-6) for p, e in zip(parsed, expected, strict=True)
        ):
            reading.fail(f"{where}: transform {workspace.transform[:80]!r} disagrees with tx, ty and scale")


def _point(action: UpstreamAction) -> tuple[float, float] | None:
    x, y = action.args.get("x"), action.args.get("y")
    return (float(x), float(y)) if _number(x) and _number(y) else None


def _number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)


def _float(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


def _names(target: ProjectTarget, hint: str) -> bool:
    """Upstream's ``sprite`` field: a lowercase sprite name, or "stage"."""
    return hint.casefold() == "stage" if target.is_stage else hint.casefold() == target.name.casefold()
