"""Turning an initial project into its golden one through composite calls, planned on a live page.

The planner works on the blocks' ids and acts on a real editor holding the initial project: every
call goes through ``compositeExecute`` exactly as an agent's would, and before each call the
page's own numbering turns ids into the ``#n`` indexes the call is written with. The calls it made
are the trajectory, so what the API refuses is found while planning, never at replay.

Per target: the variables and lists the golden has; then every initial block the golden does not
keep is deleted (after what it holds that is kept is taken out); every golden block with no match
is added; then, walking the golden scripts in order, the first block hanging in the wrong place
is moved (and whatever hangs where the golden has nothing is taken off), until none is; last,
field values and typed literals are set where they differ.
"""

from __future__ import annotations

from collections.abc import Iterator

from pydantic import BaseModel, ConfigDict, Field

from scratchworld_dist.kinds.tasks.oracle_plan._match import Matching, match_blocks
from scratchworld_dist.kinds.tasks.oracle_plan._state import ProjectState, TargetState, read_indexes, read_state
from scratchworld_dist.kinds.tasks.oracle_plan._tree import (
    chain,
    held_inputs,
    is_statement_input,
    literal,
    preorder,
    script_differences,
    top_blocks,
    variable_names,
)
from workers import composite
from workers.contract import CompositeAction
from workers.editor import Editor

MOVES_PER_BLOCK = 4
"""Bound on structural moves per golden block: a plan that needs more is not converging."""


class PlanRefusedError(Exception):
    """The API refused a call the plan needed: the message says which and why."""


class ProjectPlan(BaseModel):
    """A trajectory from an initial project to its golden, and what it could not express."""

    model_config = ConfigDict(frozen=True)

    actions: list[CompositeAction]
    modified_blocks: int
    """Distinct blocks added, deleted, moved or edited (the paper's measure of a task's size)."""

    reached_golden: bool
    """The planned project has the golden's scripts and variables in every target."""

    lacks: list[str] = Field(default_factory=list)
    """What the plan could not do, each naming the block, field, sprite or asset (empty: nothing)."""


def project_differences(golden: ProjectState, live: ProjectState) -> list[str]:
    """Scripts and variables the live project does not share with the golden, target by target."""
    problems: list[str] = []
    for wanted in golden.targets:
        have = live.target(wanted.name, wanted.is_stage)
        if have is None:
            problems.append(f"sprite {wanted.name!r} is missing")
            continue
        problems += script_differences(wanted, have)
        for kind, name in sorted(variable_names(wanted) - variable_names(have)):
            problems.append(f"{wanted.name}: {kind or 'variable'} {name!r} is missing")
    return problems


def _scope_differences(golden: ProjectState, live: ProjectState) -> list[str]:
    """Variables the golden keeps in another scope than the project does (one has no call to move them)."""
    problems: list[str] = []
    live_stage = live.target("", is_stage=True)
    shared = variable_names(live_stage) if live_stage is not None else set()
    for wanted in golden.targets:
        have = live.target(wanted.name, wanted.is_stage)
        if wanted.is_stage or have is None:
            continue
        for kind, name in sorted((variable_names(wanted) - variable_names(have)) & shared):
            problems.append(
                f"{wanted.name}: {kind or 'variable'} {name!r} is the stage's in the project and the sprite's "
                "own in the golden (the API cannot delete a variable or change its scope)"
            )
    return problems


def asset_differences(golden: ProjectState, live: ProjectState) -> list[str]:
    """Sprites, costumes and sounds that differ: changes composite mode has no call for."""
    problems: list[str] = []
    for wanted in golden.targets:
        have = live.target(wanted.name, wanted.is_stage)
        if have is None:
            problems.append(f"sprite {wanted.name!r} is added by the golden (the API cannot add sprites)")
            continue
        if have.name != wanted.name and not wanted.is_stage:
            renamed = f"sprite {have.name!r} is named {wanted.name!r} in the golden"
            problems.append(f"{renamed} (the API cannot rename sprites)")
        for kind, mine, theirs in (
            ("costumes", wanted.costumes, have.costumes),
            ("sounds", wanted.sounds, have.sounds),
        ):
            if [(a.name, a.asset_id) for a in mine] != [(a.name, a.asset_id) for a in theirs]:
                problems.append(f"{wanted.name}: its {kind} differ (the API cannot change assets)")
    kept = {id(t) for wanted in golden.targets if (t := live.target(wanted.name, wanted.is_stage)) is not None}
    for have in live.targets:
        if id(have) not in kept:
            problems.append(f"sprite {have.name!r} is removed by the golden (the API cannot delete sprites)")
    return problems


async def plan_project(editor: Editor, golden: ProjectState) -> ProjectPlan:
    """Plan (and perform) the calls that turn the project loaded in ``editor`` into ``golden``."""
    planner = _Planner(editor)
    initial = await read_state(editor)
    lacks = asset_differences(golden, initial) + _scope_differences(golden, initial)
    try:
        await planner.globals(golden, initial)
        for wanted in golden.targets:
            if initial.target(wanted.name, wanted.is_stage) is not None:
                await planner.target(wanted)
    except PlanRefusedError as exc:
        lacks.append(str(exc))
    remaining = project_differences(golden, await read_state(editor))
    lacks += [f"not reached: {problem}" for problem in remaining if not _explained(problem, lacks)]
    return ProjectPlan(
        actions=planner.actions, modified_blocks=planner.modified(), reached_golden=not remaining, lacks=lacks
    )


def _explained(problem: str, lacks: list[str]) -> bool:
    """A difference that a lack already names (the same target and thing), so it is not listed twice."""
    subject = problem.removesuffix(" is missing")
    return any(lack.startswith(subject) for lack in lacks)


class _Planner:
    def __init__(self, editor: Editor) -> None:
        self.editor = editor
        self.actions: list[CompositeAction] = []
        self.touched: set[str] = set()
        self.deleted = 0
        self.selected: str | None = None

    def modified(self) -> int:
        return len(self.touched) + self.deleted

    async def call(self, api: str, args: dict[str, object], block: str | None = None) -> dict[str, object]:
        action = CompositeAction.model_validate({"api": api, "args": args})
        envelope = await composite.execute(self.editor, action.api, action.args)
        if not envelope.success:
            code, message = (envelope.error.code, envelope.error.message) if envelope.error else ("?", "")
            raise PlanRefusedError(f"{api} {args} was refused: {code} {message}")
        self.actions.append(action)
        if block is not None:
            self.touched.add(block)
        return envelope.data if isinstance(envelope.data, dict) else {}

    async def index(self, block_id: str) -> int:
        return (await read_indexes(self.editor)).index(block_id)

    async def live(self, wanted: TargetState) -> TargetState:
        return _live_target(await read_state(self.editor), wanted)

    async def select(self, wanted: TargetState) -> None:
        if self.selected == wanted.name:
            return
        if wanted.is_stage:
            await self.call("select_stage", {})
        else:
            await self.call("select_sprite", {"name": wanted.name})
        self.selected = wanted.name

    async def globals(self, golden: ProjectState, initial: ProjectState) -> None:
        """The stage's variables and lists first: any target's blocks may use them."""
        stage = next((t for t in golden.targets if t.is_stage), None)
        have = next((t for t in initial.targets if t.is_stage), None)
        if stage is None or have is None:
            return
        for kind, name in sorted(variable_names(stage) - variable_names(have)):
            await self.call("add_list" if kind == "list" else "add_variable", {"name": name, "scope": "all"})

    async def target(self, wanted: TargetState) -> None:
        state = await read_state(self.editor)
        live, stage = _live_target(state, wanted), state.target("", is_stage=True)
        shared = variable_names(stage) if stage is not None and not wanted.is_stage else set()
        local = variable_names(wanted) - variable_names(live) - shared
        if not script_differences(wanted, live) and not local:
            return
        await self.select(wanted)
        for kind, name in sorted(local):
            await self.call("add_list" if kind == "list" else "add_variable", {"name": name, "scope": "sprite"})
        matching = match_blocks(wanted, live)
        await self._delete_unkept(wanted, set(matching.values()))
        await self._add_missing(wanted, matching)
        await self._restructure(wanted, matching)
        await self._set_values(wanted, matching)

    async def _delete_unkept(self, wanted: TargetState, kept: set[str]) -> None:
        while True:
            live = await self.live(wanted)
            doomed = next((b for b in preorder(live) if b not in kept), None)
            if doomed is None:
                return
            for child in _children(live, doomed):
                if _holds_any(live, child, kept):
                    await self.call("detach_blocks", {"blockIndex": await self.index(child)}, child)
            answer = await self.call("delete_block", {"blockIndex": await self.index(doomed)})
            self.deleted += int(answer.get("deleted", 1))  # type: ignore[call-overload]

    async def _add_missing(self, wanted: TargetState, matching: Matching) -> None:
        for block_id in preorder(wanted):
            if block_id in matching:
                continue
            block = wanted.blocks[block_id]
            creation: dict[str, str] = {}
            if "VARIABLE" in block.fields:
                creation["variableName"] = block.fields["VARIABLE"].value
            if "LIST" in block.fields:
                creation["listName"] = block.fields["LIST"].value
            args: dict[str, object] = {"blockType": block.opcode}
            if creation:
                args["creation"] = creation
            answer = await self.call("add_block", args)
            created = str(answer["blockId"])
            matching[block_id] = created
            self.touched.add(created)

    async def _restructure(self, wanted: TargetState, matching: Matching) -> None:
        order = list(_spine_first(wanted))  # the golden does not change while the live target does
        for _ in range(MOVES_PER_BLOCK * len(matching) + 10):
            move = _first_misplaced(wanted, order, await self.live(wanted), matching)
            if move is None:
                return
            api, source, placement, target = move
            indexes = await read_indexes(self.editor)
            args: dict[str, object] = {"sourceBlockIndex" if target else "blockIndex": indexes.index(source)}
            if target is not None:
                args["targetBlockIndex"] = indexes.index(target)
                args["placement"] = placement
            await self.call(api, args, source)
        raise PlanRefusedError(f"{wanted.name}: the scripts did not settle into the golden's shape")

    async def _set_values(self, wanted: TargetState, matching: Matching) -> None:
        live = await self.live(wanted)
        for block_id in preorder(wanted):
            block, mine = wanted.blocks[block_id], live.blocks[matching[block_id]]
            edits = [
                (name, field.value)
                for name, field in sorted(block.fields.items())
                if name in mine.fields and mine.fields[name].value != field.value
            ]
            for name in sorted(block.inputs):
                value = literal(wanted, block, name)
                if value is not None and value != literal(live, mine, name):
                    edits.append((name, value))
            for name, value in edits:
                args = {"blockIndex": await self.index(mine.id), "fieldName": name, "value": value}
                await self.call("set_block_field", args, mine.id)


def _live_target(state: ProjectState, wanted: TargetState) -> TargetState:
    found = state.target(wanted.name, wanted.is_stage)
    if found is None:
        raise PlanRefusedError(f"target {wanted.name!r} went away while planning")
    return found


Move = tuple[str, str, dict[str, str] | None, str | None]
"""(api, source block, placement, target block); a detach has neither placement nor target."""


def _first_misplaced(wanted: TargetState, order: list[str], live: TargetState, matching: Matching) -> Move | None:
    """The move for the first golden block in ``order`` (``_spine_first``) whose live block hangs elsewhere,
    or holds what it should not."""
    for block_id in order:
        block, mine = wanted.blocks[block_id], live.blocks[matching[block_id]]
        want = _attachment(wanted, block_id)
        have = _attachment(live, mine.id)
        if want is None and have is not None:
            return ("detach_blocks", mine.id, None, None)
        if want is not None and (have is None or (matching[want[0]], want[1]) != have):
            in_the_way = _in_the_way(wanted, live, matching, have, (matching[want[0]], want[1]))
            return _move_into(wanted, matching, in_the_way) if in_the_way else _move_into(wanted, matching, block_id)
        if block.next is None and mine.next is not None:
            return ("detach_blocks", mine.next, None, None)
        golden_inputs = dict(held_inputs(block))
        for name, held in held_inputs(mine):
            if name not in golden_inputs:
                return ("detach_blocks", held, None, None)
    return None


def _move_into(wanted: TargetState, matching: Matching, block_id: str) -> Move:
    """Connect a golden block's live block where the golden hangs it (moving it alone)."""
    parent, slot = _attachment(wanted, block_id) or ("", None)
    if slot is None:
        return ("connect_blocks", matching[block_id], {"kind": "stack_after"}, matching[parent])
    kind = "statement_into" if is_statement_input(slot) else "value_into"
    return ("connect_blocks", matching[block_id], {"kind": kind, "inputName": slot}, matching[parent])


def _in_the_way(
    wanted: TargetState,
    live: TargetState,
    matching: Matching,
    have: tuple[str, str | None] | None,
    want: tuple[str, str | None],
) -> str | None:
    """The golden block whose live block sits where this one should, this one hanging under it as its next:
    moving that one away (its next takes its place) puts both right in one move, as a person fixes a stack."""
    if have is None or have[1] is not None:
        return None
    blocker = have[0]
    if _attachment(live, blocker) != want:
        return None
    golden_id = next((g for g, live_id in matching.items() if live_id == blocker), None)
    if golden_id is None or _attachment(wanted, golden_id) is None:
        return None
    return golden_id


def _attachment(target: TargetState, block_id: str) -> tuple[str, str | None] | None:
    """(parent, input) where a block hangs (input None: it is the parent's next), or None when top-level."""
    parent_id = target.blocks[block_id].parent
    if parent_id is None or parent_id not in target.blocks:
        return None
    parent = target.blocks[parent_id]
    if parent.next == block_id:
        return (parent_id, None)
    return next(((parent_id, name) for name, held in held_inputs(parent) if held == block_id), None)


def _spine_first(target: TargetState) -> Iterator[str]:
    """Script by script: a chain's blocks with what their value inputs hold, then what each C-slot holds.

    Building a script's spine before filling its C-slots keeps every drop near the end of a short stack,
    where the primitive oracle's gestures find a clean path (a drop below a filled C-block meets the
    connections inside it first)."""

    def visit(first: str) -> Iterator[str]:
        ids = chain(target, first)
        for block_id in ids:
            yield from reporters(block_id)
        for block_id in ids:
            for name, held in held_inputs(target.blocks[block_id]):
                if is_statement_input(name):
                    yield from visit(held)

    def reporters(block_id: str) -> Iterator[str]:
        yield block_id
        for name, held in held_inputs(target.blocks[block_id]):
            if not is_statement_input(name):
                yield from reporters(held)

    for top in top_blocks(target):
        yield from visit(top)


def _children(target: TargetState, block_id: str) -> list[str]:
    block = target.blocks[block_id]
    return [held for _, held in held_inputs(block)] + ([block.next] if block.next else [])


def _holds_any(target: TargetState, block_id: str, kept: set[str]) -> bool:
    stack = [block_id]
    while stack:
        current = stack.pop()
        if current in kept:
            return True
        stack += _children(target, current)
    return False
