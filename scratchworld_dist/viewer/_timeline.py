"""A job's steps as its page shows them: the observation (and what changed), the reply, the action drawn.

Everything here is plain data for the job template; nothing is escaped here (the template does it).
"""

from __future__ import annotations

import difflib
import json
from typing import Literal

from pydantic import BaseModel, JsonValue

from workers.contract import StepRecord

PAGE_SIZE = (1280, 720)
"""The page every screenshot is taken of, in CSS px at pixel ratio 1 (``BrowserConfig.viewport``)."""

DiffKind = Literal["same", "added", "removed"]


class DiffLine(BaseModel):
    kind: DiffKind
    text: str


class Box(BaseModel):
    """An element of the list, as a box over the screenshot (percent of the page, for any display size)."""

    label: str
    left: float
    top: float
    width: float
    height: float


class Mark(BaseModel):
    """The step's gesture drawn over the screenshot, in page px (the overlay's viewBox is the page)."""

    kind: Literal["point", "drag"]
    x: float
    y: float
    x2: float | None = None
    y2: float | None = None
    snapped: bool | None = None
    """A drag that connected a block (None when the record does not say)."""

    label: str


class Message(BaseModel):
    role: str
    text: str
    images: list[str]
    """Image digests the message showed (files in the attempt's images/)."""


class StepView(BaseModel):
    index: int
    action: str
    args: str
    ok: bool
    error_code: str | None
    error_message: str | None
    data: str | None
    warnings: list[str]
    latency_s: float
    llm_calls: int
    cost_usd: float
    analysis: str | None
    """The reasoning the reply gave before its action (``Analysis: ...``), when it has that shape."""

    reply: str | None
    prompt: list[Message]
    text: list[DiffLine] | None
    """Composite: the observation, marked against the previous one."""

    changed: int
    """Lines of the observation added or removed since the previous one."""

    screenshot: str | None
    boxes: list[Box]
    mark: Mark | None


def step_views(steps: list[StepRecord]) -> list[StepView]:
    views, previous = [], None
    for step in steps:
        seen = step.observation
        text = seen.text if seen is not None else None
        lines = _diff(previous, text) if text is not None else None
        if text is not None:
            previous = text
        views.append(
            StepView(
                index=step.index,
                action=step.action,
                args=json.dumps(step.args, ensure_ascii=False, sort_keys=True),
                ok=step.ok,
                error_code=step.error_code,
                error_message=step.error_message,
                data=None if step.data is None else json.dumps(step.data, ensure_ascii=False, indent=1)[:20_000],
                warnings=step.warnings,
                latency_s=step.latency_s,
                llm_calls=step.llm_calls,
                cost_usd=step.cost_usd,
                analysis=_analysis(step.reply),
                reply=step.reply,
                prompt=[_message(m) for m in step.prompt],
                text=lines,
                changed=sum(line.kind != "same" for line in lines or []),
                screenshot=seen.screenshot if seen is not None else None,
                boxes=[_box(e.index, e.type, e.text, e.x, e.y, e.width, e.height) for e in seen.elements]
                if seen is not None
                else [],
                mark=_mark(step),
            )
        )
    return views


def _diff(before: str | None, after: str) -> list[DiffLine]:
    if before is None:
        return [DiffLine(kind="same", text=line) for line in after.splitlines()]
    lines = []
    for line in difflib.ndiff(before.splitlines(), after.splitlines()):
        tag, text = line[:2], line[2:]
        if tag == "? ":
            continue
        kind: DiffKind = "added" if tag == "+ " else "removed" if tag == "- " else "same"
        lines.append(DiffLine(kind=kind, text=text))
    return lines


def _analysis(reply: str | None) -> str | None:
    if not reply:
        return None
    _, found, rest = reply.partition("Analysis:")
    if not found:
        return None
    return rest.split("```", 1)[0].strip() or None


def _message(message: JsonValue) -> Message:
    if not isinstance(message, dict):
        return Message(role="?", text=json.dumps(message)[:2000], images=[])
    role = str(message.get("role", "?"))
    content = message.get("content")
    if isinstance(content, str):
        return Message(role=role, text=content, images=[])
    texts, images = [], []
    for part in content if isinstance(content, list) else []:
        if isinstance(part, dict) and part.get("type") == "text":
            texts.append(str(part.get("text", "")))
        elif isinstance(part, dict) and part.get("type") == "image_ref":
            images.append(str(part.get("sha256", "")))
    return Message(role=role, text="\n".join(texts), images=[d for d in images if _hex(d)])


def _box(index: int, kind: str, text: str, x: int, y: int, width: int, height: int) -> Box:
    page_w, page_h = PAGE_SIZE
    return Box(
        label=f"{index}  {kind}  {text}"[:200],
        left=100 * x / page_w,
        top=100 * y / page_h,
        width=100 * width / page_w,
        height=100 * height / page_h,
    )


def _mark(step: StepRecord) -> Mark | None:
    """Where the gesture went, from what the environment answered (it resolves index targets to points)."""
    data = step.data if isinstance(step.data, dict) else {}
    if step.action in ("click", "double_click") and _number(data.get("x")) and _number(data.get("y")):
        return Mark(kind="point", x=data["x"], y=data["y"], label=step.action)  # type: ignore[arg-type]
    start, end = data.get("start"), data.get("end")
    if step.action == "drag_and_drop" and _point(start) and _point(end):
        snapped = data.get("snapped")
        label = "drag: snapped" if snapped is True else "drag: not snapped" if snapped is False else "drag"
        return Mark(
            kind="drag",
            x=start[0],  # type: ignore[index]
            y=start[1],  # type: ignore[index]
            x2=end[0],  # type: ignore[index]
            y2=end[1],  # type: ignore[index]
            snapped=snapped if isinstance(snapped, bool) else None,
            label=label,
        )
    return None


def _number(value: JsonValue) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _point(value: JsonValue) -> bool:
    return isinstance(value, list) and len(value) == 2 and all(_number(v) for v in value)


def _hex(digest: str) -> bool:
    return len(digest) == 64 and all(c in "0123456789abcdef" for c in digest)
