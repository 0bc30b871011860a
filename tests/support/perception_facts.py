"""Hand-made view facts for tests of derivation: blocks placed by rectangle, fully visible unless told.

Rects are page px (x, y, width, height); the visible area defaults to a 700x600 workspace at (300, 90).
"""

from __future__ import annotations

from scratchworld_dist.kinds.perception.items._facts import (
    BlockFacts,
    FieldFacts,
    InputFacts,
    LabelFacts,
    Point,
    Rect,
    Seen,
    ViewFacts,
)

AREA = (300.0, 90.0, 700.0, 600.0)
POINTS = 100


def seen(share: float, points: int = POINTS) -> Seen:
    return Seen(seen=round(share * points), points=points)


def field(
    name: str, kind: str, text: str, rect: tuple[float, float, float, float] = (0, 0, 10, 10), *, share: float = 1.0,
    shown: str | None = None, options: list[str] | None = None,
) -> FieldFacts:  # fmt: skip
    return FieldFacts(
        name=name, kind=kind, text=text, shown=text if shown is None else shown, rect=Rect(x=rect[0], y=rect[1],
        width=rect[2], height=rect[3]), visibility=seen(share, 20), options=options,
    )  # fmt: skip


def slot(name: str, kind: str, block: str | None = None) -> InputFacts:
    return InputFacts(name=name, kind=kind, block=block)


def block(
    id: str,
    opcode: str,
    rect: tuple[float, float, float, float],
    *,
    parent: str | None = None,
    input: str | None = None,
    next: str | None = None,
    body: float = 1.0,
    label: float = 1.0,
    top: float = 1.0,
    bottom: float = 1.0,
    text_height: float = 12.0,
    reporter: bool = False,
    fields: list[FieldFacts] | None = None,
    inputs: list[InputFacts] | None = None,
    xy: tuple[float, float] = (0.0, 0.0),
) -> BlockFacts:
    return BlockFacts(
        id=id, opcode=opcode, parent=parent, input=input, next=next, xy=Point(x=xy[0], y=xy[1]),
        rect=Rect(x=rect[0], y=rect[1], width=rect[2], height=rect[3]), reporter=reporter, body=seen(body),
        top=seen(top, 20), bottom=seen(bottom, 20), label=LabelFacts(text=opcode, seen=round(label * 40), points=40,
        height=text_height), fields=fields or [], inputs=inputs or [],
    )  # fmt: skip


def view(*blocks: BlockFacts, area: tuple[float, float, float, float] = AREA, scale: float = 0.675) -> ViewFacts:
    return ViewFacts(
        target="Sprite1", area=Rect(x=area[0], y=area[1], width=area[2], height=area[3]), scale=scale,
        blocks=list(blocks),
    )  # fmt: skip


def changed(facts: BlockFacts, **changes: object) -> BlockFacts:
    """``facts`` with some fields replaced; ``body``, ``top``, ``bottom`` and ``label`` are given as shares,
    ``y`` and ``x`` move its rectangle."""
    update: dict[str, object] = {}
    for name, value in changes.items():
        if name in ("body", "top", "bottom"):
            update[name] = seen(float(value), getattr(facts, name).points)  # type: ignore[arg-type]
        elif name == "label":
            update[name] = facts.label.model_copy(update={"seen": round(float(value) * facts.label.points)})  # type: ignore[arg-type]
        elif name in ("x", "y"):
            update["rect"] = facts.rect.model_copy(update={name: value})
        else:
            update[name] = value
    return facts.model_copy(update=update)
