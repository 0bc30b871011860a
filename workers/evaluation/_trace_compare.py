"""Where two observable traces first differ: the evidence that a variant is not the golden.

Both traces are replayed side by side, frame by frame; since they agree up to a frame, only the fields
either one changed in that frame can differ there, so each frame costs what it recorded. Targets are
matched by key (name; clones by creation order); variables by id, their values always, their names only
where a monitor shows them. A variable only one trace has is left out unless its monitor is shown: a
renamed variable, or a hidden helper a refactoring added, is nothing a user sees.
"""

from __future__ import annotations

from collections.abc import Iterable

from pydantic import BaseModel, ConfigDict, JsonValue

from workers.evaluation._trace import EVENT_FIELDS, STAGE, VARIABLE_PREFIX, ObservableTrace, TraceFrame

PRESENT = "present"
"""The field of a difference in which a target exists in one trace only (values: whether it exists)."""


class TraceDifference(BaseModel):
    """The first observable difference: in which frame, on which target, which field, and each trace's value."""

    model_config = ConfigDict(frozen=True)

    frame: int
    target: str
    field: str
    """A field of the trace (``x``, ``bubble``, ``sounds``, ``pen``...), ``present``, or for a variable
    ``var:<id>`` (one trace has it, shown) or ``var:<id>.value`` / ``.name`` / ``.monitor``."""
    a: JsonValue
    b: JsonValue
    variable: str | None = None
    """The variable's name (in the first trace that has it), for a variable's field."""

    def describe(self) -> str:
        """One line for people: ``frame 12, Cat, bubble: ['say', 'hi'] vs ['say', 'hello']``."""
        what = f"{self.field} ({self.variable})" if self.variable else self.field
        return f"frame {self.frame}, {self.target}, {what}: {self.a!r} vs {self.b!r}"


class _Replay:
    """One trace's state as its frames are applied in order, and the events of the current frame."""

    def __init__(self, trace: ObservableTrace) -> None:
        self.frames = {frame.frame: frame for frame in trace.frames}
        self.state: dict[str, dict[str, JsonValue]] = {}
        self.events: dict[str, dict[str, JsonValue]] = {}

    def apply(self, index: int, touched: set[tuple[str, str]]) -> None:
        """Apply frame ``index`` (if recorded) and add what it changed to ``touched``."""
        self.events = {}
        frame: TraceFrame | None = self.frames.get(index)
        if frame is None:
            return
        for key, fields in frame.targets.items():
            lasting = {name: value for name, value in fields.items() if name not in EVENT_FIELDS}
            self.events[key] = {name: value for name, value in fields.items() if name in EVENT_FIELDS}
            touched.update((key, name) for name in fields)
            if lasting:  # only sounds: a clone that played and went within the frame is never there
                if key not in self.state:
                    self.state[key] = {}
                    touched.add((key, PRESENT))
                self.state[key].update(lasting)
        for key in frame.removed:
            if self.state.pop(key, None) is not None:
                touched.add((key, PRESENT))


FIELD_ORDER = (PRESENT, "x", "y", "direction", "size", "costume", "visible", "effects", "rotation", "bubble", "sounds")
"""Which of a frame's differences on one target is named first (the stage's ``layers``, ``pen``, ``question``
and variables, by name, come after)."""


def _order(item: tuple[str, str]) -> tuple[bool, str, int, str]:
    key, name = item
    rank = FIELD_ORDER.index(name) if name in FIELD_ORDER else len(FIELD_ORDER)
    return (key != STAGE, key, rank, name)


def _shown(variable: JsonValue) -> bool:
    return isinstance(variable, list) and len(variable) == 3 and bool(variable[2])


def _variable_difference(index: int, key: str, name: str, a: JsonValue, b: JsonValue) -> TraceDifference | None:
    if a is None or b is None:  # only one trace has it: a difference only if a monitor shows it
        if _shown(a) or _shown(b):
            return TraceDifference(frame=index, target=key, field=name, a=a, b=b, variable=_name(a, b))
        return None
    if not (isinstance(a, list) and isinstance(b, list)):
        return None if a == b else TraceDifference(frame=index, target=key, field=name, a=a, b=b)
    parts = [("value", 1), ("monitor", 2)] + ([("name", 0)] if _shown(a) or _shown(b) else [])
    for part, position in parts:
        if a[position] != b[position]:
            return TraceDifference(
                frame=index, target=key, field=f"{name}.{part}", a=a[position], b=b[position], variable=_name(a, b)
            )
    return None


def _name(a: JsonValue, b: JsonValue) -> str | None:
    for variable in (a, b):
        if isinstance(variable, list) and variable and isinstance(variable[0], str):
            return variable[0]
    return None


def _compare(
    index: int, replays: tuple[_Replay, _Replay], touched: Iterable[tuple[str, str]]
) -> TraceDifference | None:
    first, second = replays
    for key, name in sorted(touched, key=_order):
        if name in EVENT_FIELDS:  # what happened this frame, whether or not the target is still there
            a = first.events.get(key, {}).get(name, [])
            b = second.events.get(key, {}).get(name, [])
            if a != b:
                return TraceDifference(frame=index, target=key, field=name, a=a, b=b)
            continue
        in_a, in_b = key in first.state, key in second.state
        if in_a != in_b:
            return TraceDifference(frame=index, target=key, field=PRESENT, a=in_a, b=in_b)
        if not in_a or name == PRESENT:
            continue
        a, b = first.state[key].get(name), second.state[key].get(name)
        if name.startswith(VARIABLE_PREFIX):
            difference = _variable_difference(index, key, name, a, b)
            if difference is not None:
                return difference
        elif a != b:
            return TraceDifference(frame=index, target=key, field=name, a=a, b=b)
    return None


def first_difference(a: ObservableTrace, b: ObservableTrace) -> TraceDifference | None:
    """The first frame, target and field in which ``a`` and ``b`` show something different; None if none.

    Frames are compared up to the first one a truncated trace left out: None then means "no difference
    in what both recorded" (check ``truncated``). A run that ended earlier stays as it ended.
    """
    cut = [trace.truncated_at for trace in (a, b) if trace.truncated_at is not None]
    limit = min(cut) if cut else None
    replays = (_Replay(a), _Replay(b))
    for index in sorted(set(replays[0].frames) | set(replays[1].frames)):
        if limit is not None and index >= limit:
            break
        touched: set[tuple[str, str]] = set()
        for replay in replays:
            replay.apply(index, touched)
        difference = _compare(index, replays, touched)
        if difference is not None:
            return difference
    return None
