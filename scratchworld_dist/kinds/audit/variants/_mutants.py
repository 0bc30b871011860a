"""Mutation operators: each makes a project wrong in one small way, at one place.

Every operator proposes its changes over the blocks that can run (``_places.live_places``), in project
order; ``enumerate_mutants`` makes them in operator order, leaving out a change that does nothing (``0``
replaced by ``0``, two equal statements swapped) or only what an earlier mutant did (``repeat 10`` made
``11`` by ``loop_count`` is not made again by ``number_literal``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import scratchworld_dist.kinds.audit.variants._edits as edits
from scratchworld_dist.kinds.audit.variants._places import (
    TEXT_CODE,
    Place,
    as_number,
    is_cap,
    is_statement,
    js_round,
    literal_inputs,
    live_places,
    number_value,
)
from scratchworld_dist.kinds.audit.variants._program import (
    BROADCAST_CODE,
    LIST_CODE,
    VARIABLE_CODE,
    Field,
    Primitive,
    Program,
    ProgramFormatError,
)
from scratchworld_dist.kinds.audit.variants._variant import Candidate, Mutant, VariantMaker, sample

ARITHMETIC = ("operator_add", "operator_subtract", "operator_multiply", "operator_divide", "operator_mod")
COMPARISON = ("operator_lt", "operator_gt", "operator_equals")
BOOLEAN = ("operator_and", "operator_or")

KEYS = ("space", "up arrow", "down arrow", "left arrow", "right arrow", "a")
"""Keys a key hat is moved to (the first that is not its own)."""

EVENT_HATS = ("event_whenflagclicked", "event_whenkeypressed", "event_whenbroadcastreceived")
"""Hats ``event_hat`` changes (and the click hat of a sprite or the stage)."""

NEVER_SENT = "audit: never sent"
"""The message a hat or a broadcast is moved to when the project has no other."""

Edit = Callable[[Program], None]


def _on(target: str, edit: Callable[..., None], *args: Any) -> Edit:
    return lambda program: edit(program.target(target), *args)


def _candidate(operator: str, place: Place, change: str, what: str, apply: Edit) -> Candidate:
    description = f"{place.target.name}: {what} (script under {place.top.opcode})"
    return Candidate(operator, place.target.name, place.block.id, change, description, apply)


def delete_statement(program: Program) -> Iterator[Candidate]:
    for place in live_places(program):
        if is_statement(place.target, place.block):
            edit = _on(place.target.name, edits.delete_statement, place.block.id)
            yield _candidate("delete_statement", place, "delete", f"delete {place.block.opcode}", edit)


def swap_statements(program: Program) -> Iterator[Candidate]:
    for place in live_places(program):
        block, target = place.block, place.target
        if is_statement(target, block) and block.next is not None and not is_cap(target.block(block.next)):
            below = target.block(block.next).opcode
            edit = _on(target.name, edits.swap_with_next, block.id)
            yield _candidate("swap_statements", place, "swap with next", f"swap {block.opcode} and {below}", edit)


def unwrap_forever(program: Program) -> Iterator[Candidate]:
    for place in live_places(program):
        if place.block.opcode == "control_forever" and is_statement(place.target, place.block):
            edit = _on(place.target.name, edits.unwrap, place.block.id)
            yield _candidate("unwrap_forever", place, "unwrap", "run the forever loop's body once", edit)


def swap_if_else(program: Program) -> Iterator[Candidate]:
    for place in live_places(program):
        if place.block.opcode == "control_if_else" and {"SUBSTACK", "SUBSTACK2"} & set(place.block.inputs):
            edit = _on(place.target.name, edits.swap_inputs, place.block.id, "SUBSTACK", "SUBSTACK2")
            yield _candidate("swap_if_else", place, "swap branches", "swap the if and else branches", edit)


def loop_count(program: Program) -> Iterator[Candidate]:
    """``repeat N`` runs one time more or less (a change the VM's rounding would undo is not made)."""
    for place, name, literal, number in _numbers(program, "control_repeat", "TIMES"):
        for new in (number + 1, number - 1):
            if max(0, js_round(new)) != max(0, js_round(number)):
                yield _literal(
                    "loop_count", place, name, literal.value, number_value(new, literal.value), "repeat count"
                )


def wait_duration(program: Program) -> Iterator[Candidate]:
    """``wait T`` waits no time, or twice as long (``wait 0`` waits a second)."""
    for place, name, literal, number in _numbers(program, "control_wait", "DURATION"):
        for new in (0.0, 2 * number) if number > 0 else (1.0,):
            yield _literal("wait_duration", place, name, literal.value, number_value(new, literal.value), "wait")


def number_literal(program: Program) -> Iterator[Candidate]:
    """A number becomes 0, 1, its negation, or one more or less."""
    for place, name, literal, number in _numbers(program, None, None):
        tried = {number}
        for new in (0.0, 1.0, -number, number + 1, number - 1):
            if new not in tried:
                tried.add(new)
                yield _literal("number_literal", place, name, literal.value, number_value(new, literal.value), "number")


def text_literal(program: Program) -> Iterator[Candidate]:
    """A text becomes empty, changes case, or is one character off."""
    for place in live_places(program):
        for name, literal in literal_inputs(place.block):
            if literal.code != TEXT_CODE or as_number(literal.value) is not None:
                continue
            text = str(literal.value)
            changed_case = text.upper() if text != text.upper() else text.lower()
            for new in dict.fromkeys(("", changed_case, _one_off(text))):
                if new != text:
                    yield _literal("text_literal", place, name, literal.value, new, "text")


def _one_off(text: str) -> str:
    """``text`` with its last character the next one of its kind (``cat`` -> ``cau``, ``9`` -> ``0``)."""
    if not text:
        return "a"
    last = text[-1]
    for first, size in (("a", 26), ("A", 26), ("0", 10)):
        if 0 <= ord(last) - ord(first) < size:
            return text[:-1] + chr(ord(first) + (ord(last) - ord(first) + 1) % size)
    return text[:-1] + ("x" if last != "x" else "y")


def _numbers(
    program: Program, opcode: str | None, input_name: str | None
) -> Iterator[tuple[Place, str, Primitive, float]]:
    """Number literals (in number slots, or numbers typed in text slots) of ``opcode``'s ``input_name``
    (of any block when None)."""
    for place in live_places(program):
        if opcode is not None and place.block.opcode != opcode:
            continue
        for name, literal in literal_inputs(place.block):
            number = as_number(literal.value)
            if number is not None and (input_name is None or name == input_name):
                yield place, name, literal, number


def _literal(operator: str, place: Place, name: str, old: Any, new: Any, what: str) -> Candidate:
    edit = _on(place.target.name, edits.set_literal, place.block.id, name, new)
    change = f"{name}: {old!r} -> {new!r}"
    return _candidate(operator, place, change, f"{what} {old!r} -> {new!r} in {place.block.opcode}", edit)


def _opcode_swaps(operator: str, group: tuple[str, ...]) -> Callable[[Program], Iterator[Candidate]]:
    def propose(program: Program) -> Iterator[Candidate]:
        for place in live_places(program):
            if place.block.opcode in group:
                for other in group:
                    if other != place.block.opcode:
                        edit = _on(place.target.name, edits.set_opcode, place.block.id, other)
                        change = f"{place.block.opcode} -> {other}"
                        yield _candidate(operator, place, change, change, edit)

    propose.__doc__ = f"An operator becomes another of {', '.join(group)}."
    return propose


def drop_not(program: Program) -> Iterator[Candidate]:
    for place in live_places(program):
        if place.block.opcode == "operator_not":
            edit = _on(place.target.name, edits.lift_input, place.block.id, "OPERAND")
            yield _candidate("drop_not", place, "drop not", "drop a not", edit)


def event_hat(program: Program) -> Iterator[Candidate]:
    """A hat waits for another event: the green flag, another key, a click, another message."""
    messages = _messages(program)
    for place in live_places(program):
        block, target = place.block, place.target
        if block.parent is not None:
            continue
        clicked = "event_whenstageclicked" if target.is_stage else "event_whenthisspriteclicked"
        if block.opcode not in (
            "event_whenflagclicked",
            "event_whenkeypressed",
            clicked,
            "event_whenbroadcastreceived",
        ):
            continue
        key = block.fields.get("KEY_OPTION", Field(None)).value
        message = block.fields.get("BROADCAST_OPTION", Field(None)).value
        options = [
            ("event_whenflagclicked", None),
            ("event_whenkeypressed", next(k for k in KEYS if k != key)),
            (clicked, None),
            *(("event_whenbroadcastreceived", m) for m in _others(messages, message)),
        ]
        for opcode, detail in options:
            if opcode == block.opcode and detail is None:
                continue  # the very same event
            edit = _hat_edit(target.name, block.id, opcode, detail)
            change = f"{block.opcode} -> {opcode}" + (f" {detail}" if detail else "")
            yield _candidate("event_hat", place, change, f"hat {change}", edit)


def _hat_edit(target: str, block_id: str, opcode: str, detail: str | None) -> Edit:
    def edit(program: Program) -> None:
        fields: dict[str, Field] = {}
        if opcode == "event_whenkeypressed":
            fields["KEY_OPTION"] = Field(detail, None)
        elif opcode == "event_whenbroadcastreceived":
            fields["BROADCAST_OPTION"] = Field(detail, _message_id(program, str(detail)))
        edits.set_hat(program.target(target), block_id, opcode, fields)

    return edit


def broadcast_message(program: Program) -> Iterator[Candidate]:
    """A broadcast sends another message (one the project declares, else one nobody receives)."""
    messages = _messages(program)
    for place in live_places(program):
        if place.block.opcode not in ("event_broadcast", "event_broadcastandwait"):
            continue
        literal = place.block.inputs.get("BROADCAST_INPUT")
        sent = literal.literal if literal is not None else None
        if sent is None or sent.code != BROADCAST_CODE:
            continue
        for other in _others(messages, sent.value):
            edit = _reference_edit(place, "BROADCAST_INPUT", lambda p, name=other: (name, _message_id(p, name)))
            yield _candidate("broadcast_message", place, f"{sent.value} -> {other}", f"broadcast {other}", edit)


def _messages(program: Program) -> list[str]:
    return sorted(dict.fromkeys(str(name) for name in program.stage.broadcasts.values()))


def _others(messages: list[str], current: object) -> list[str]:
    others = [m for m in messages if m.lower() != str(current).lower()]  # Scratch matches messages in any case
    return others or [NEVER_SENT]


def _message_id(program: Program, name: str) -> str:
    found = next((i for i, n in program.stage.broadcasts.items() if n == name), None)
    return found if found is not None else edits.add_broadcast(program, name, f"broadcast:{name}")


def _reference_edit(place: Place, input_name: str, choose: Callable[[Program], tuple[str, str]]) -> Edit:
    def edit(program: Program) -> None:
        value = program.target(place.target.name).block(place.block.id).inputs[input_name].value
        if not isinstance(value, Primitive):
            raise ProgramFormatError(f"{place.target.name}: input {input_name} of {place.block.id!r} names nothing")
        edits.set_reference(value, *choose(program))

    return edit


def _other_reference(
    operator: str, code: int, field_name: str, opcodes: frozenset[str] | None
) -> Callable[[Program], Iterator[Candidate]]:
    kind = "variable" if code == VARIABLE_CODE else "list"

    def propose(program: Program) -> Iterator[Candidate]:
        for place in live_places(program):
            scope = program.in_scope(place.target, kind)
            uses: list[tuple[str | None, str]] = [
                (name, entry.value.ref_id)
                for name, entry in place.block.inputs.items()
                if isinstance(entry.value, Primitive) and entry.value.code == code and entry.value.ref_id
            ]
            used_field = place.block.fields.get(field_name)
            if used_field is not None and used_field.id and (opcodes is None or place.block.opcode in opcodes):
                uses.append((None, used_field.id))
            for input_name, current in uses:
                for other_id, other in sorted(scope.items(), key=lambda item: (item[1], item[0])):
                    if other_id == current:
                        continue
                    slot = input_name or field_name
                    change = f"{slot}: {scope.get(current, current)} -> {other}"
                    if input_name is None:
                        edit = _on(place.target.name, edits.set_field, place.block.id, field_name, other, other_id)
                    else:
                        edit = _reference_edit(place, input_name, lambda _p, n=other, i=other_id: (n, i))
                    yield _candidate(operator, place, change, f"read the {kind} {other} instead", edit)

    propose.__doc__ = f"A block reads or sets another {kind} in scope."
    return propose


VARIABLE_WRITERS = frozenset({"data_variable", "data_setvariableto", "data_changevariableby"})

OPERATORS: dict[str, Callable[[Program], Iterator[Candidate]]] = {
    "delete_statement": delete_statement,
    "swap_statements": swap_statements,
    "unwrap_forever": unwrap_forever,
    "swap_if_else": swap_if_else,
    "loop_count": loop_count,
    "wait_duration": wait_duration,
    "number_literal": number_literal,
    "text_literal": text_literal,
    "arithmetic_operator": _opcode_swaps("arithmetic_operator", ARITHMETIC),
    "comparison_operator": _opcode_swaps("comparison_operator", COMPARISON),
    "boolean_operator": _opcode_swaps("boolean_operator", BOOLEAN),
    "drop_not": drop_not,
    "event_hat": event_hat,
    "broadcast_message": broadcast_message,
    "other_variable": _other_reference("other_variable", VARIABLE_CODE, "VARIABLE", VARIABLE_WRITERS),
    "other_list": _other_reference("other_list", LIST_CODE, "LIST", None),
}
"""Every mutation operator by its stable name, in the order mutants are made."""


def mutant_candidates(program: Program) -> Iterator[Candidate]:
    for propose in OPERATORS.values():
        yield from propose(program)


def enumerate_mutants(project: dict[str, Any]) -> list[Mutant]:
    """Every mutant of a project (its project.json), in a deterministic order: by operator, then place."""
    maker = VariantMaker(project)
    return maker.mutants(mutant_candidates(maker.program))


def sample_mutants(project: dict[str, Any], n: int, seed: int | str) -> list[Mutant]:
    """``n`` mutants spread over the operators, the same for the same project and seed."""
    return sample(enumerate_mutants(project), n, seed)
