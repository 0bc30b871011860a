"""Edits of a program that keep its links whole: every ``next`` has a ``parent`` that points back, every input
block names its block as parent, top-level blocks have a place on the workspace.

Statements are the blocks of a stack: the one after a hat, in a C-block's substack, or after another. A
statement hangs from the block before it (``next``), from a C-block's input, or from nothing (top-level).
"""

from __future__ import annotations

from typing import Any

from scratchworld_dist.kinds.audit.variants._program import (
    INPUT_BLOCK,
    INPUT_OBSCURED,
    INPUT_SHADOW,
    REFERENCE_CODE,
    REFERENCE_FIELD,
    Block,
    Field,
    Input,
    Primitive,
    Program,
    ProgramFormatError,
    Target,
    VarKind,
)

Hook = tuple[str | None, str | None]
"""Where a statement hangs: (the block above, the input it is in) -- (above, None) for ``next``, and
(None, None) for a top-level block."""


def hook_of(target: Target, block_id: str) -> Hook:
    parent_id = target.block(block_id).parent
    if parent_id is None:
        return None, None
    parent = target.block(parent_id)
    if parent.next == block_id:
        return parent_id, None
    for name, entry in parent.inputs.items():
        if entry.value == block_id:
            return parent_id, name
    raise ProgramFormatError(
        f"target {target.name!r}: block {block_id!r} names {parent_id!r} as parent, which has it nowhere"
    )


def hang(target: Target, hook: Hook, child: str | None, position: tuple[Any, Any] | None = None) -> None:
    """Put ``child`` (a stack's first block, or nothing) where ``hook`` points; at the top level it takes
    ``position``."""
    above, input_name = hook
    if above is None:
        if child is not None:
            block = target.block(child)
            block.parent, block.top_level = None, True
            block.position = block.position or position or (0, 0)
        return
    parent = target.block(above)
    if input_name is None:
        parent.next = child
    else:
        set_input_block(target, above, input_name, child)
    if child is not None:
        block = target.block(child)
        block.parent, block.top_level, block.position = above, False, None


def set_input_block(target: Target, block_id: str, input_name: str, child: str | None) -> None:
    """Plug ``child`` into an input (or empty it: a shadow it covered shows again, an empty slot goes away)."""
    block = target.block(block_id)
    entry = block.inputs.get(input_name)
    if child is None:
        if entry is not None and entry.has_shadow and entry.shadow is not None:
            block.inputs[input_name] = Input(INPUT_SHADOW, entry.shadow)
        else:
            block.inputs.pop(input_name, None)
        return
    if entry is None or (entry.kind == INPUT_SHADOW and not entry.has_shadow and entry.value is None):
        block.inputs[input_name] = Input(INPUT_BLOCK, child)
    elif entry.kind == INPUT_SHADOW:
        block.inputs[input_name] = Input(INPUT_OBSCURED, child, entry.value, has_shadow=True)
    else:
        entry.value = child
    target.block(child).parent = block_id


def remove(target: Target, block_id: str) -> None:
    """Delete a block that is already unhooked, with everything in its inputs; comments on them stay loose."""
    gone = set(target.subtree(block_id))
    for removed in gone:
        del target.blocks[removed]
    for comment in target.comments.values():
        if isinstance(comment, dict) and comment.get("blockId") in gone:
            comment["blockId"] = None


def delete_statement(target: Target, block_id: str) -> None:
    """Take a statement out of its stack, the block above now followed by the one below."""
    block = target.block(block_id)
    below = block.next
    hang(target, hook_of(target, block_id), below, block.position)
    block.next = None
    remove(target, block_id)


def swap_with_next(target: Target, block_id: str) -> None:
    """Exchange a statement and the one below it."""
    first = target.block(block_id)
    if first.next is None:
        raise ProgramFormatError(f"target {target.name!r}: block {block_id!r} has no block below it")
    second = target.block(first.next)
    hook, position = hook_of(target, block_id), first.position
    below = second.next
    first.next = below
    if below is not None:
        target.block(below).parent = first.id
    second.next = first.id
    first.parent, first.top_level, first.position = second.id, False, None
    hang(target, hook, second.id, position)


def unwrap(target: Target, block_id: str, input_name: str = "SUBSTACK") -> None:
    """Replace a C-block by its substack: the body runs once, where the block was."""
    block = target.block(block_id)
    body = block.inputs[input_name].block_id if input_name in block.inputs else None
    below = block.next
    hook = hook_of(target, block_id)
    block.inputs.pop(input_name, None)
    block.next = None
    if body is None:
        hang(target, hook, below, block.position)
    else:
        last = target.stack(body)[-1]
        target.block(last).next = below
        if below is not None:
            target.block(below).parent = last
        hang(target, hook, body, block.position)
    remove(target, block_id)


def lift_input(target: Target, block_id: str, input_name: str) -> None:
    """Replace a reporter by the block in one of its inputs (``not (x)`` becomes ``x``)."""
    block = target.block(block_id)
    inner = block.inputs[input_name].block_id if input_name in block.inputs else None
    above, slot = hook_of(target, block_id)
    if above is None or slot is None:
        raise ProgramFormatError(f"target {target.name!r}: block {block_id!r} is in no input")
    block.inputs.pop(input_name, None)
    set_input_block(target, above, slot, inner)
    remove(target, block_id)


def swap_inputs(target: Target, block_id: str, first: str, second: str) -> None:
    """Exchange what two inputs hold (operands, branches); an absent input stays absent on the other side."""
    inputs = target.block(block_id).inputs
    a, b = inputs.pop(first, None), inputs.pop(second, None)
    if b is not None:
        inputs[first] = b
    if a is not None:
        inputs[second] = a


def set_literal(target: Target, block_id: str, input_name: str, value: Any) -> None:
    """Replace the literal an input shows (the slot keeps its kind: number, text...)."""
    literal = target.block(block_id).inputs[input_name].literal
    if literal is None:
        raise ProgramFormatError(f"target {target.name!r}: input {input_name} of {block_id!r} shows no literal")
    literal.value = value


def set_field(target: Target, block_id: str, name: str, value: Any, ref_id: str | None = None) -> None:
    """Set a field's value (and the id of the variable, list or broadcast it names)."""
    fields = target.block(block_id).fields
    current = fields.get(name)
    fields[name] = Field(value, ref_id, has_id=True if current is None else current.has_id or ref_id is not None)


def add_block(target: Target, block: Block) -> Block:
    if block.id in target.blocks:
        raise ProgramFormatError(f"target {target.name!r} already has a block {block.id!r}")
    target.blocks[block.id] = block
    return block


def move_to_end(target: Target, top: str) -> None:
    """Put a script's blocks last in the project: the script starts after the target's others."""
    for block_id in target.script_blocks(top):
        target.blocks[block_id] = target.blocks.pop(block_id)


def add_broadcast(program: Program, name: str, seed: str) -> str:
    """Declare a message on the stage (where Scratch keeps them all); its id."""
    broadcast_id = program.fresh_id(seed)
    program.stage.broadcasts[broadcast_id] = name
    return broadcast_id


def add_variable(program: Program, target: Target, kind: VarKind, name: str, value: Any, seed: str) -> str:
    """Declare a variable (or list) on ``target``: for this sprite only, or global on the stage; its id."""
    var_id = program.fresh_id(seed)
    (target.variables if kind == "variable" else target.lists)[var_id] = [name, value]
    return var_id


def rename(program: Program, kind: VarKind, var_id: str, new_name: str) -> None:
    """Rename a variable (or list) and every use: fields, reporters, loose reporters, monitors, and
    ``sensing_of`` reading it from another sprite. A global one is used in every target, a local one only
    in its own (ids are unique per target, not always per project)."""
    owner = next(t for t in program.targets if var_id in (t.variables if kind == "variable" else t.lists))
    entry = (owner.variables if kind == "variable" else owner.lists)[var_id]
    old_name = entry[0]
    entry[0] = new_name
    for target in program.targets if owner.is_stage else [owner]:
        for item in target.blocks.values():
            if isinstance(item, Primitive):
                _rename_primitive(item, kind, var_id, new_name)
                continue
            reference = item.fields.get(REFERENCE_FIELD[kind])
            if reference is not None and reference.id == var_id:
                reference.value = new_name
            for slot in item.inputs.values():
                for value in (slot.value, slot.shadow):
                    if isinstance(value, Primitive):
                        _rename_primitive(value, kind, var_id, new_name)
    if kind == "variable":
        _rename_readers(program, owner, old_name, new_name)
    for monitor in program.raw.get("monitors") or []:
        if not isinstance(monitor, dict) or monitor.get("id") != var_id:
            continue
        params = monitor.get("params")
        if isinstance(params, dict) and REFERENCE_FIELD[kind] in params:
            params[REFERENCE_FIELD[kind]] = new_name


def _rename_primitive(value: Primitive, kind: VarKind, var_id: str, new_name: str) -> None:
    if value.code == REFERENCE_CODE[kind] and value.ref_id == var_id:
        value.value = new_name


def _rename_readers(program: Program, owner: Target, old_name: str, new_name: str) -> None:
    """``(old_name) of (owner)`` reads a variable by name: it follows the rename."""
    menu_value = "_stage_" if owner.is_stage else owner.name
    for target in program.targets:
        for block in target.all_blocks():
            prop, menu = block.fields.get("PROPERTY"), block.inputs.get("OBJECT")
            if block.opcode != "sensing_of" or prop is None or prop.value != old_name or menu is None:
                continue
            shown = target.blocks.get(menu.value) if isinstance(menu.value, str) else None
            if (
                isinstance(shown, Block)
                and shown.shadow
                and shown.fields.get("OBJECT", Field(None)).value == menu_value
            ):
                prop.value = new_name


def set_opcode(target: Target, block_id: str, opcode: str) -> None:
    """Make a block another of the same shape (``+`` into ``-``): its inputs and fields stay."""
    target.block(block_id).opcode = opcode


def set_hat(target: Target, block_id: str, opcode: str, fields: dict[str, Field]) -> None:
    """Make a hat wait for another event (its fields name the key or message)."""
    block = target.block(block_id)
    block.opcode, block.fields = opcode, fields


def set_reference(value: Primitive, name: str, ref_id: str) -> None:
    """Point an inline variable, list or broadcast at another one."""
    value.value = name
    value.rest = [ref_id, *value.rest[1:]]
