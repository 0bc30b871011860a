"""An attempt's episode video as its job page plays it: the file, and the steps' marks on its timeline.

A step is placed on the video by its wall-clock start (``StepRecord.started_at``) against the video's
(``VideoInfo.started_at``); its mark (where it clicked, the path it dragged, what it typed, its number)
shows from then until the next step begins. The page's script (``static/video.js``) draws the marks over
the playing video and seeks to a step when the step is clicked.
"""

from __future__ import annotations

import json
from pathlib import Path

from pydantic import BaseModel, JsonValue, ValidationError

from scratchworld_dist.results import VIDEO_FILE, VIDEO_INFO_FILE
from workers.contract import StepRecord, VideoInfo

MARK_HOLD_S = 1.5
"""How long the last step's mark stays up after the step's own time (a step with no successor)."""

TEXT_LIMIT = 80
"""Characters of typed text (or a composite action's arguments) a mark shows."""


class VideoMark(BaseModel):
    """One step on the video's timeline (times in seconds into the video; points in page px)."""

    index: int
    start_s: float
    end_s: float
    label: str
    """The step's number and action (``#3 click``)."""

    ok: bool
    point: tuple[float, float] | None = None
    """Where a click went."""

    path: tuple[float, float, float, float] | None = None
    """A drag's start and end."""

    snapped: bool | None = None
    text: str | None = None
    """What a step typed or pressed, or a composite action's arguments, shortened."""


class VideoView(BaseModel):
    href: str
    """The video, relative to the job's page."""

    info: VideoInfo
    marks_json: str
    """The marks as JSON for the page's script (``<`` escaped: it sits in a ``<script>`` element)."""

    marks: int


def video_view(folder: Path | None, files: str | None, steps: list[StepRecord]) -> VideoView | None:
    """The attempt's video, if it has one (``folder``: its artifact folder; ``files``: the same under the run's
    ``files/``), with its steps' marks."""
    if folder is None or files is None or not (folder / VIDEO_FILE).is_file():
        return None
    try:
        info = VideoInfo.model_validate_json((folder / VIDEO_INFO_FILE).read_bytes())
    except (OSError, ValidationError):
        return None  # a video that cannot be lined up with its steps is not shown
    marks = video_marks(info, steps)
    data = json.dumps([m.model_dump(exclude_none=True) for m in marks], ensure_ascii=True, separators=(",", ":"))
    return VideoView(
        href=f"../files/{files}/{VIDEO_FILE}",
        info=info,
        marks_json=data.replace("<", "\\u003c"),
        marks=len(marks),
    )


def video_marks(info: VideoInfo, steps: list[StepRecord]) -> list[VideoMark]:
    """The steps that have a wall-clock start (older runs' steps have none), placed on the video."""
    timed = [step for step in steps if step.started_at is not None]
    marks = []
    for number, step in enumerate(timed):
        start = max(0.0, (step.started_at or 0.0) - info.started_at)
        following = timed[number + 1].started_at if number + 1 < len(timed) else None
        end = following - info.started_at if following is not None else start + step.latency_s + MARK_HOLD_S
        marks.append(_mark(step, round(start, 3), round(max(end, start), 3)))
    return marks


def _mark(step: StepRecord, start_s: float, end_s: float) -> VideoMark:
    data = step.data if isinstance(step.data, dict) else {}
    mark = VideoMark(index=step.index, start_s=start_s, end_s=end_s, label=f"#{step.index} {step.action}", ok=step.ok)
    if step.action in ("click", "double_click") and _numbers(data.get("x"), data.get("y")):
        return mark.model_copy(update={"point": (data["x"], data["y"])})
    start, end = data.get("start"), data.get("end")
    if step.action == "drag_and_drop" and isinstance(start, list) and isinstance(end, list) and _numbers(*start, *end):
        snapped = data.get("snapped")
        return mark.model_copy(
            update={"path": (*start, *end), "snapped": snapped if isinstance(snapped, bool) else None}
        )
    if step.action == "scroll" and _numbers(step.args.get("x"), step.args.get("y")):  # where the wheel turned
        point = (step.args["x"], step.args["y"])
        return mark.model_copy(update={"point": point, "text": _text(step)})
    return mark.model_copy(update={"text": _text(step)})


def _text(step: StepRecord) -> str | None:
    """What a keyboard step typed or pressed; a composite action's arguments."""
    args, data = step.args, step.data if isinstance(step.data, dict) else {}
    if step.action == "type" and isinstance(args.get("text"), str):
        text = f"typed “{args['text']}”"
    elif step.action == "key" and data.get("key") is not None:
        text = f"key {data['key']}"
    elif step.action == "hotkey" and isinstance(data.get("keys"), list):
        text = "keys " + "+".join(str(key) for key in data["keys"])  # type: ignore[union-attr]
    elif args:
        text = json.dumps(args, ensure_ascii=False, sort_keys=True)
    else:
        return None
    return text if len(text) <= TEXT_LIMIT else text[: TEXT_LIMIT - 1] + "…"


def _numbers(*values: JsonValue) -> bool:
    return bool(values) and all(isinstance(v, int | float) and not isinstance(v, bool) for v in values)
