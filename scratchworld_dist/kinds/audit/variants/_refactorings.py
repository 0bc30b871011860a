"""Refactorings: the same behaviour written otherwise, which a sound grader passes.

Each is behaviour-preserving for what a program does on the stage and in its variables; what else changes
(and a grader could look at) is said in its docstring. Only scripts under a hat are rewritten.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import scratchworld_dist.kinds.audit.variants._edits as edits
from scratchworld_dist.kinds.audit.variants._places import (
    NUMBER_CODES,
    as_number,
    is_cap,
    is_hat,
    is_statement,
    js_round,
    live_places,
)
from scratchworld_dist.kinds.audit.variants._program import (
    BROADCAST_CODE,
    INPUT_BLOCK,
    INPUT_OBSCURED,
    INPUT_SHADOW,
    VARIABLE_CODE,
    Block,
    Field,
    Input,
    Primitive,
    Program,
    Target,
    VarKind,
)
from scratchworld_dist.kinds.audit.variants._variant import Candidate, Refactoring, VariantMaker, sample

MOVE_BY = (160, 80)
"""How far ``move_script`` moves a script on the workspace."""

SPLIT_OFFSET = 480
"""How far right of its script the tail split off by ``split_at_broadcast`` is placed."""

PURE_REPORTERS = frozenset(
    {
        *(f"operator_{name}" for name in ("add", "subtract", "multiply", "divide", "mod", "round", "mathop")),
        *(f"operator_{name}" for name in ("lt", "gt", "equals", "and", "or", "not", "join", "letter_of")),
        *(f"operator_{name}" for name in ("length", "contains")),
        "data_variable",
        "data_listcontents",
        "data_itemoflist",
        "data_itemnumoflist",
        "data_lengthoflist",
        "data_listcontainsitem",
        "motion_xposition",
        "motion_yposition",
        "motion_direction",
        "looks_size",
        "looks_costumenumbername",
        "looks_backdropnumbername",
        "sound_volume",
        *(f"sensing_{name}" for name in ("touchingobject", "touchingcolor", "coloristouchingcolor", "distanceto")),
        *(f"sensing_{name}" for name in ("answer", "keypressed", "mousedown", "mousex", "mousey", "loudness")),
        *(f"sensing_{name}" for name in ("timer", "of", "current", "dayssince2000", "username")),
        "argument_reporter_string_number",
        "argument_reporter_boolean",
    }
)
"""Reporters that only read: evaluating them in another order changes nothing (``operator_random`` draws, and
extension reporters may wait, so neither is here)."""

Edit = Callable[[Program], None]


def _candidate(operator: str, target: Target, block_id: str, change: str, description: str, edit: Edit) -> Candidate:
    return Candidate(operator, target.name, block_id, change, f"{target.name}: {description}", edit)


def rename(program: Program, kind: VarKind) -> Iterator[Candidate]:
    """Every variable (or list) renamed, with every use: its fields and reporters in every script that can
    see it, loose reporters, monitors, and ``(name) of (sprite)``. A grader that looks it up by a name
    the instruction never gave is what this finds; one whose task names the variable may rightly fail it."""
    taken = {str(e[0]) for t in program.targets for pool in (t.variables, t.lists) for e in pool.values()}
    for target in program.targets:
        for var_id, entry in (target.variables if kind == "variable" else target.lists).items():
            name = str(entry[0])
            new = _unused(f"{name} renamed", taken)
            edit = _rename_edit(kind, var_id, new)
            yield _candidate(f"rename_{kind}", target, var_id, f"{name} -> {new}", f"rename {kind} {name}", edit)


def _rename_edit(kind: VarKind, var_id: str, new: str) -> Edit:
    return lambda program: edits.rename(program, kind, var_id, new)


def _unused(name: str, taken: set[str]) -> str:
    candidate, n = name, 1
    while candidate in taken:
        n += 1
        candidate = f"{name} {n}"
    return candidate


def move_script(program: Program) -> Iterator[Candidate]:
    """A script elsewhere on the workspace (the editor's layout only)."""
    for target in program.targets:
        for top in target.scripts():
            x, y = target.block(top).position or (0, 0)
            if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in (x, y)):
                continue
            to = (x + MOVE_BY[0], y + MOVE_BY[1])
            edit = _on(target.name, lambda t, top=top, to=to: setattr(t.block(top), "position", to))
            yield _candidate("move_script", target, top, f"({x}, {y}) -> {to}", "move a script", edit)


def reorder_scripts(program: Program) -> Iterator[Candidate]:
    """A script moved last in its sprite's blocks. Scripts started by one event start in that order, so only
    a script no other script of its sprite shares a trigger with is moved (key hats all share one: "any"
    key overlaps every key). A grader that takes "the first script" or "the first such block" sees it."""
    for target in program.targets:
        tops = [top for top in target.scripts() if is_hat(target.block(top).opcode)]
        triggers = [_trigger(target.block(top)) for top in tops]
        for index, top in enumerate(tops[:-1]):
            if triggers.count(triggers[index]) == 1:
                edit = _on(target.name, edits.move_to_end, top)
                opcode = target.block(top).opcode
                yield _candidate("reorder_scripts", target, top, "to the end", f"move the {opcode} script last", edit)


def _trigger(hat: Block) -> tuple[str, str]:
    if hat.opcode == "event_whenkeypressed":
        return hat.opcode, ""
    return hat.opcode, "|".join(str(f.value).lower() for _, f in sorted(hat.fields.items()))


def split_at_broadcast(program: Program) -> Iterator[Candidate]:
    """``broadcast and wait (m); rest`` becomes ``broadcast and wait (m); broadcast and wait (new)`` and the rest
    goes under a new ``when I receive (new)``, placed to the right. It adds a message (a grader listing
    broadcasts sees it), and the rest runs in its own thread: later in the same frame than other threads
    started before it, and not stopped when the first script's hat restarts it. Not done in a sprite that
    may have clones (all clones would receive the new message) nor in a custom block's definition (a
    block run without screen refresh would no longer run the rest so)."""
    for place in live_places(program):
        block, target = place.block, place.target
        if block.opcode != "event_broadcastandwait" or block.next is None or not is_statement(target, block):
            continue
        if place.top.opcode in ("procedures_definition", "control_start_as_clone") or _may_clone(program, target):
            continue
        yield _candidate(
            "split_at_broadcast",
            target,
            block.id,
            "split after",
            "split the script after a broadcast and wait",
            _split_edit(target.name, block.id, place.top.id),
        )


def _may_clone(program: Program, target: Target) -> bool:
    """Whether any script may make a clone of ``target``."""
    if target.is_stage:
        return False
    for other in program.targets:
        for block in other.all_blocks():
            option = block.fields.get("CLONE_OPTION") if block.opcode == "control_create_clone_of_menu" else None
            if option is not None and option.value in (target.name, "_myself_" if other is target else None):
                return True
            menu = block.inputs.get("CLONE_OPTION") if block.opcode == "control_create_clone_of" else None
            if menu is not None and menu.kind != INPUT_SHADOW:  # a clone of whatever a reporter names
                return True
    return False


def _split_edit(target_name: str, block_id: str, top_id: str) -> Edit:
    def edit(program: Program) -> None:
        target = program.target(target_name)
        taken = {str(name).lower() for name in program.stage.broadcasts.values()}
        name = _unused("split", taken)
        message = edits.add_broadcast(program, name, f"split:{target_name}:{block_id}")
        split = target.block(block_id)
        tail = split.next
        sender = program.fresh_id(f"split-sender:{target_name}:{block_id}")
        send = Block(sender, "event_broadcastandwait", parent=block_id)
        send.inputs["BROADCAST_INPUT"] = Input(INPUT_SHADOW, Primitive(BROADCAST_CODE, name, [message]))
        edits.add_block(target, send)
        split.next = sender
        x, y = target.block(top_id).position or (0, 0)
        hat_id = program.fresh_id(f"split-hat:{target_name}:{block_id}")
        hat = Block(
            hat_id, "event_whenbroadcastreceived", next=tail, top_level=True, position=(_num(x) + SPLIT_OFFSET, y)
        )
        hat.fields["BROADCAST_OPTION"] = Field(name, message)
        edits.add_block(target, hat)
        if tail is not None:
            target.block(tail).parent = hat_id

    return edit


def _num(value: Any) -> float:
    return value if isinstance(value, int | float) and not isinstance(value, bool) else 0


def counter_loop(program: Program) -> Iterator[Candidate]:
    """``repeat N {body}`` becomes ``set c to 0; repeat until (c = N) {body; change c by 1}`` with a new
    variable ``c`` of the sprite (a grader listing variables, or the stage's monitors, sees it). Only for a
    literal N (a reporter would be read once by ``repeat`` and at every turn by ``repeat until``), written
    as the count ``repeat`` makes of it, outside custom blocks (a recursive call would share ``c``), and
    when the body does not end in a block nothing may follow."""
    for place in live_places(program):
        block, target = place.block, place.target
        times = block.inputs.get("TIMES")
        literal = times.literal if times is not None else None
        if block.opcode != "control_repeat" or literal is None or literal.code not in NUMBER_CODES | {10}:
            continue
        number = as_number(literal.value)
        body = block.inputs["SUBSTACK"].block_id if "SUBSTACK" in block.inputs else None
        ends_in_cap = body is not None and is_cap(target.block(target.stack(body)[-1]))
        if number is None or ends_in_cap or place.top.opcode == "procedures_definition":
            continue
        count = max(0, js_round(number))
        edit = _counter_edit(target.name, block.id, count)
        yield _candidate("counter_loop", target, block.id, f"repeat {count}", "repeat as a counter loop", edit)


def _counter_edit(target_name: str, block_id: str, count: int) -> Edit:
    def edit(program: Program) -> None:
        target = program.target(target_name)
        seed = f"counter:{target_name}:{block_id}"
        taken = {str(e[0]) for t in program.targets for e in t.variables.values()}
        name = _unused("counter", taken)
        var = edits.add_variable(program, target, "variable", name, 0, seed)
        loop = target.block(block_id)
        hook = edits.hook_of(target, block_id)
        ids = {part: program.fresh_id(f"{seed}:{part}") for part in ("set", "equals", "change")}
        reporter = Primitive(VARIABLE_CODE, name, [var])
        setter = Block(ids["set"], "data_setvariableto", next=block_id)
        setter.fields["VARIABLE"] = Field(name, var)
        setter.inputs["VALUE"] = Input(INPUT_SHADOW, Primitive(10, "0"))
        equals = Block(ids["equals"], "operator_equals", parent=block_id)
        equals.inputs["OPERAND1"] = Input(INPUT_OBSCURED, reporter, Primitive(10, ""), has_shadow=True)
        equals.inputs["OPERAND2"] = Input(INPUT_SHADOW, Primitive(10, str(count)))
        change = Block(ids["change"], "data_changevariableby")
        change.fields["VARIABLE"] = Field(name, var)
        change.inputs["VALUE"] = Input(INPUT_SHADOW, Primitive(4, "1"))
        for new in (setter, equals, change):
            edits.add_block(target, new)
        body = loop.inputs["SUBSTACK"].block_id if "SUBSTACK" in loop.inputs else None
        if body is None:
            loop.inputs["SUBSTACK"] = Input(INPUT_BLOCK, change.id)
            change.parent = block_id
        else:
            last = target.block(target.stack(body)[-1])
            last.next, change.parent = change.id, last.id
        position = loop.position
        edits.hang(target, hook, setter.id, position)
        loop.parent, loop.top_level, loop.position = setter.id, False, None
        loop.opcode = "control_repeat_until"
        del loop.inputs["TIMES"]
        loop.inputs = {"CONDITION": Input(INPUT_BLOCK, equals.id), **loop.inputs}

    return edit


def commute_operands(program: Program) -> Iterator[Candidate]:
    """``a + b`` becomes ``b + a`` (and ``a * b``), when neither operand has an effect."""
    yield from _swapped_operands(program, "commute_operands", ("operator_add", "operator_multiply"), "NUM1", "NUM2")


def swap_boolean_arms(program: Program) -> Iterator[Candidate]:
    """``a and b`` becomes ``b and a`` (and ``or``), when neither arm has an effect (Scratch evaluates both)."""
    yield from _swapped_operands(program, "swap_boolean_arms", ("operator_and", "operator_or"), "OPERAND1", "OPERAND2")


def _swapped_operands(
    program: Program, operator: str, opcodes: tuple[str, ...], first: str, second: str
) -> Iterator[Candidate]:
    for place in live_places(program):
        block, target = place.block, place.target
        if block.opcode in opcodes and all(_pure(target, block.inputs.get(n)) for n in (first, second)):
            edit = _on(target.name, edits.swap_inputs, block.id, first, second)
            yield _candidate(
                operator, target, block.id, f"{first} <-> {second}", f"swap the operands of {block.opcode}", edit
            )


def _pure(target: Target, entry: Input | None) -> bool:
    """Whether evaluating the input only reads (a literal, a variable, reporters that only read)."""
    ref = entry.block_id if entry is not None else None
    if ref is None:
        return True
    return all(
        isinstance(b := target.blocks.get(block_id), Block) and (b.shadow or b.opcode in PURE_REPORTERS)
        for block_id in target.subtree(ref)
    )


def _on(target: str, edit: Callable[..., None], *args: Any) -> Edit:
    return lambda program: edit(program.target(target), *args)


REFACTORINGS: dict[str, Callable[[Program], Iterator[Candidate]]] = {
    "rename_variable": lambda program: rename(program, "variable"),
    "rename_list": lambda program: rename(program, "list"),
    "move_script": move_script,
    "reorder_scripts": reorder_scripts,
    "split_at_broadcast": split_at_broadcast,
    "counter_loop": counter_loop,
    "commute_operands": commute_operands,
    "swap_boolean_arms": swap_boolean_arms,
}
"""Every refactoring by its stable name, in the order they are made."""


def refactoring_candidates(program: Program) -> Iterator[Candidate]:
    for propose in REFACTORINGS.values():
        yield from propose(program)


def enumerate_refactorings(project: dict[str, Any]) -> list[Refactoring]:
    """Every refactoring of a project (its project.json), in a deterministic order: by kind, then place."""
    maker = VariantMaker(project)
    return maker.refactorings(refactoring_candidates(maker.program))


def sample_refactorings(project: dict[str, Any], n: int, seed: int | str) -> list[Refactoring]:
    """``n`` refactorings spread over their kinds, the same for the same project and seed."""
    return sample(enumerate_refactorings(project), n, seed)
