"""The primitive oracle: solves a task through pixels only, by acting out its golden trajectory.

It proves the drag mechanics of primitive mode: every composite action of the golden trajectory
becomes real clicks, drags, wheel turns and key presses, aimed at block geometry read live from the
page (``geometry.js``), and the editor alone decides what a gesture does (snap, insert, bump).

How it works:

1. ``begin`` replays the trajectory through the composite API on the page (the *dry run*) to learn
   which block every index argument denotes (the trajectory's indices depend on positions, which
   differ in a GUI run) and the semantic project state after every step; then it reloads the
   initial project.
2. ``act`` hands out one gesture at a time. Between gestures it only *reads* the page; it never
   writes to the VM or the workspace.
3. After every step the GUI project must mean exactly what the dry run's did (scripts, fields,
   variables; not ids or positions), checked with a bounded wait. A gesture without the expected
   effect raises ``OracleDivergenceError`` with what differs, so the oracle never silently goes on.
"""

from __future__ import annotations

import json
from collections.abc import AsyncIterator, Awaitable, Callable
from dataclasses import dataclass
from typing import Any

from pydantic import JsonValue

from workers import composite
from workers.contract import Action, BridgeError, CompositeAction, Done, PrimitiveAction, ScratchWorldError
from workers.editor import Editor

CATEGORIES = {
    "motion_": "Motion",
    "looks_": "Looks",
    "sound_": "Sound",
    "event_": "Events",
    "control_": "Control",
    "sensing_": "Sensing",
    "operator_": "Operators",
    "data_": "Variables",
}
"""The palette category of each opcode prefix (the English labels of the category menu)."""

INDEX_ARGS = ("sourceBlockIndex", "targetBlockIndex", "blockIndex")
VARIABLE_FIELDS = ("VARIABLE", "LIST", "BROADCAST_OPTION")
"""Fields whose dropdown items are names (the VM stores the name, Blockly the id)."""

NEW_MESSAGE = "New message"
CLEAN_UP = "Clean up Blocks"
TYPE_ATTEMPTS = 3
WAIT_MS = 5000
DRAG_DURATION = 0.3
DRAG_STEPS = max(10, int(DRAG_DURATION * 30))
"""Mouse moves of one drag: the rule of ``Gestures`` (30 per second of duration, at least 10)."""
SNAPSHOT_WAIT_MS = 4000
MAX_SCROLLS = 4
ROOM_SCROLLS = 2
"""Wheel turns down the workspace when its visible part has no room for a dropped block."""
FLYOUT_MARGIN = 24
"""Pixels between a palette block and the palette's edge after scrolling it into view."""
MAX_WHEEL = 5000
"""The largest wheel turn ``Gestures`` accepts."""

Point = tuple[float, float]


class OracleDivergenceError(ScratchWorldError):
    """A gesture did not have the effect the oracle planned, or the editor is not in the planned state."""


@dataclass(frozen=True)
class PlannedStep:
    """One composite action of the trajectory, as the dry run saw it."""

    number: int
    """1-based position in the trajectory."""
    action: CompositeAction
    blocks: dict[str, str]
    """Index argument name -> identity of the block it denoted in the dry run: ``path:<structural path
    in the initial project>`` or ``new:<dry-run id of the block a step added>``."""
    data: dict[str, Any]
    """What the composite call answered."""
    new_fields: dict[str, Any] | None
    """For add_block: the VM fields and input values the dry run gave the new block."""
    snapshot: str
    """The semantic project state after the step (geometrySnapshot's JSON text)."""

    def describe(self) -> str:
        return f"step {self.number} {self.action.api} {json.dumps(self.action.args, sort_keys=True)}"


class PrimitiveOracle:
    """Scripted primitive-mode agent: the golden trajectory as gestures, one per ``act``."""

    observes = False

    def __init__(self, initial_project: bytes, trajectory: list[CompositeAction]) -> None:
        self._initial = initial_project
        self._trajectory = list(trajectory)
        self._editor: Editor | None = None
        self._plan: list[PlannedStep] = []
        self._initial_snapshot = ""
        self._live: dict[str, str] = {}
        """Block identity (see ``PlannedStep.blocks``) -> id of the block in the GUI run."""
        self._gestures: AsyncIterator[PrimitiveAction] | None = None
        self.gesture_count = 0
        """Gestures handed out so far."""

    @property
    def plan(self) -> list[PlannedStep]:
        return list(self._plan)

    async def begin(self, editor: Editor) -> None:
        """Dry-run the trajectory on the loaded project, then reload it for the real run."""
        self._editor = editor
        before = await self._snapshot()
        paths = await self._paths()
        self._initial_snapshot = before
        try:
            self._plan = await self._dry_run(paths)
        finally:
            await editor.load_project(self._initial)
            await editor.set_stage_size("small")
        await self._wait("quiet", timeout_ms=10_000, what="the reloaded project to be drawn")
        if await self._snapshot() != before:
            raise OracleDivergenceError("reloading the initial project did not restore its scripts")
        # Ids of compact blocks (variable reporters in inputs) are new on every load: map by path.
        reloaded = {
            f"path:{path}": block for target in (await self._paths()).values() for block, path in target.items()
        }
        if set(reloaded) != {f"path:{path}" for target in paths.values() for path in target.values()}:
            raise OracleDivergenceError("reloading the initial project did not restore its blocks")
        self._live = reloaded
        self._gestures = self._solve()

    async def act(self, observation: object | None) -> Action:
        if self._gestures is None:
            raise RuntimeError("PrimitiveOracle.begin(editor) must run before act()")
        try:
            gesture = await anext(self._gestures)
        except StopAsyncIteration:
            return Done()
        self.gesture_count += 1
        return gesture

    # ---------- the dry run ----------

    async def _dry_run(self, paths: dict[str, dict[str, str]]) -> list[PlannedStep]:
        editor = self._require_editor()
        plan: list[PlannedStep] = []
        editing = json.loads(self._initial_snapshot)["editingTarget"]
        for number, action in enumerate(self._trajectory, start=1):
            blocks: dict[str, str] = {}
            if any(isinstance(action.args.get(name), int) for name in INDEX_ARGS):
                ids = _ids(await editor.call("compositeBlockIds"))
                initial = paths.get(editing, {})
                for name in INDEX_ARGS:
                    index = action.args.get(name)
                    if isinstance(index, int) and 0 < index < len(ids) and ids[index]:
                        block = str(ids[index])
                        blocks[name] = f"path:{initial[block]}" if block in initial else f"new:{block}"
            envelope = await composite.execute(editor, action.api, action.args)
            if not envelope.success or envelope.error is not None:
                error = envelope.error
                reason = f"{error.code}: {error.message}" if error else "no reason given"
                raise OracleDivergenceError(f"the golden trajectory fails in composite mode at step {number}: {reason}")
            data = envelope.data if isinstance(envelope.data, dict) else {}
            new_fields = None
            if action.api == "add_block":
                new_fields = _dict(await editor.call("geometryBlockFields", {"id": data["blockId"]}))
            snapshot = await self._snapshot()
            editing = json.loads(snapshot)["editingTarget"]
            plan.append(PlannedStep(number, action, blocks, dict(data), new_fields, snapshot))
        return plan

    # ---------- the real run ----------

    async def _solve(self) -> AsyncIterator[PrimitiveAction]:
        handlers: dict[str, Callable[[PlannedStep], AsyncIterator[PrimitiveAction]]] = {
            "select_sprite": self._select_sprite,
            "select_stage": self._select_stage,
            "add_variable": self._add_variable,
            "add_list": self._add_variable,
            "add_block": self._add_block,
            "connect_blocks": self._connect_blocks,
            "detach_blocks": self._detach_blocks,
            "set_block_field": self._set_block_field,
            "delete_block": self._delete_block,
        }
        for step in self._plan:
            handler = handlers.get(step.action.api)
            if handler is None:
                raise OracleDivergenceError(f"{step.describe()}: no gestures are known for {step.action.api}")
            await self._wait("quiet", what=f"the editor to settle before {step.describe()}")
            async for gesture in handler(step):
                yield gesture
            await self._expect_state(step.snapshot, f"after {step.describe()}")
        expected = self._plan[-1].snapshot if self._plan else self._initial_snapshot
        await self._expect_state(expected, "at the end of the run")

    async def _expect_state(self, expected: str, when: str) -> None:
        result = _dict(
            await self._editor_call(
                "geometryWait", {"until": "snapshot", "args": {"expected": expected}}, SNAPSHOT_WAIT_MS
            )
        )
        if not result.get("ok"):
            difference = describe_difference(json.loads(expected), result.get("value"))
            raise OracleDivergenceError(f"{when}, the GUI project differs from the composite dry run: {difference}")

    # ---------- targets ----------

    async def _select_sprite(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        name = str(step.data.get("editingTarget"))
        layout = await self._layout()
        if layout["editingTarget"] == name:
            return
        tiles = [tile for tile in layout["targets"]["sprites"] if tile["name"] == name]
        if len(tiles) != 1:
            found = [tile["name"] for tile in layout["targets"]["sprites"]]
            raise OracleDivergenceError(f"{step.describe()}: no single sprite tile named {name!r} (tiles: {found})")
        yield click(*centre(tiles[0]["rect"]))
        await self._wait("editingTarget", {"name": name}, what=f"sprite {name!r} to be selected")

    async def _select_stage(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        name = str(step.data.get("editingTarget"))
        layout = await self._layout()
        if layout["editingTarget"] == name:
            return
        rect = layout["targets"]["stage"]
        if rect is None:
            raise OracleDivergenceError(f"{step.describe()}: the stage tile is not on the page")
        yield click(rect["x"] + rect["width"] / 2, rect["y"] + min(60.0, rect["height"] / 2))
        await self._wait("editingTarget", {"name": name}, what="the stage to be selected")

    # ---------- variables ----------

    async def _add_variable(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        created = step.data.get("created") or {}
        if not created.get("created"):
            return  # the composite call reused an existing one: nothing to make
        button = "Make a List" if step.action.api == "add_list" else "Make a Variable"

        async def locate() -> dict[str, Any]:
            return _dict(await self._editor_call("geometryFlyoutButton", {"text": button}))

        async for gesture in self._show_in_palette(locate, "Variables", f"{step.describe()}: the {button!r} button"):
            yield gesture
        yield click(*centre((await locate())["rect"]))
        async for gesture in self._fill_prompt(str(created["name"]), _scope_option(str(created["scope"]))):
            yield gesture

    async def _fill_prompt(self, text: str, option: str | None = None) -> AsyncIterator[PrimitiveAction]:
        """Type into the GUI's prompt modal, pick a radio option, press OK."""
        await self._wait("modalOpen", what="the prompt to open")
        modal = _dict(await self._editor_call("geometryModal"))
        field = modal["inputs"][0]
        if not field["focused"]:
            yield click(*centre(field["rect"]))
        if field["value"]:
            yield PrimitiveAction(api="hotkey", args={"keys": ["ctrl", "a"]})
        yield PrimitiveAction(api="type", args={"text": text})
        if option is not None:
            modal = _dict(await self._editor_call("geometryModal"))
            choices = [o for o in modal["options"] if o["text"] == option]
            if not choices:
                offered = [o["text"] for o in modal["options"]]
                raise OracleDivergenceError(f"the prompt {modal['title']!r} offers no {option!r} (options: {offered})")
            if not choices[0]["checked"]:
                yield click(*centre(choices[0]["rect"]))
        modal = _dict(await self._editor_call("geometryModal"))
        if modal["inputs"][0]["value"] != text:
            raise OracleDivergenceError(
                f"the prompt {modal['title']!r} holds {modal['inputs'][0]['value']!r}, not {text!r}"
            )
        ok = [b for b in modal["buttons"] if b["text"] == "OK"]
        if not ok:
            raise OracleDivergenceError(f"the prompt {modal['title']!r} has no OK button")
        yield click(*centre(ok[0]["rect"]))
        await self._wait("modalClosed", what="the prompt to close")

    # ---------- blocks from the palette ----------

    async def _add_block(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        opcode = str(step.action.args["blockType"])
        creation = step.action.args.get("creation") or {}
        variable = None
        if opcode in ("data_variable", "data_listcontents") and isinstance(creation, dict):
            name = creation.get("variableName" if opcode == "data_variable" else "listName")
            variable = str(name) if name is not None else None
        category = next((name for prefix, name in CATEGORIES.items() if opcode.startswith(prefix)), None)
        if category is None:
            raise OracleDivergenceError(f"{step.describe()}: no palette category holds {opcode}")

        async def locate() -> dict[str, Any]:
            return _dict(await self._editor_call("geometryFlyoutBlock", {"opcode": opcode, "variableName": variable}))

        what = f"{step.describe()}: {opcode}" + (f" for {variable!r}" if variable else "")
        async for gesture in self._show_in_palette(locate, category, what):
            yield gesture
        anchor_of = await self._anchor(step)
        if anchor_of is not None:
            async for gesture in self._scroll_into_view(
                lambda: _points(anchor_of()), f"{step.describe()} (its partner)"
            ):
                yield gesture
        palette = await self._palette_block(opcode, variable)
        ratio = palette["workspaceScale"] / palette["flyoutScale"]
        rect = palette["rect"]
        spot = None
        for _ in range(ROOM_SCROLLS + 1):
            near = await anchor_of() if anchor_of is not None else None
            spot = await self._free_spot(rect["width"] * ratio, rect["height"] * ratio, near)
            if spot is not None:
                break
            async for gesture in self._scroll_for_room():
                yield gesture
        if spot is None:
            raise OracleDivergenceError(f"{step.describe()}: no empty part of the workspace can take the block")
        grab = palette["grab"]
        end = (spot[0] + (grab["x"] - rect["x"]) * ratio, spot[1] + (grab["y"] - rect["y"]) * ratio)
        known = [block["id"] for block in (await self._top_blocks())["vm"]]
        yield drag((grab["x"], grab["y"]), end)
        result = await self._wait_result("newBlock", {"opcode": opcode, "known": known})
        if not result.get("ok"):
            raise OracleDivergenceError(
                f"{step.describe()}: dropping {opcode} from the palette at {_fmt(end)} did not leave exactly one new "
                f"top-level {opcode} (new ones: {result.get('value')}); did it snap to a script?"
            )
        live_id = str(result["value"])
        self._live[f"new:{step.data['blockId']}"] = live_id
        async for gesture in self._match_new_fields(step, live_id):
            yield gesture

    async def _show_in_palette(
        self, locate: Callable[[], Awaitable[dict[str, Any]]], category: str, what: str
    ) -> AsyncIterator[PrimitiveAction]:
        """Wheel the palette until what ``locate`` finds is usable (visible, and grabbable if a block).

        The palette holds every category in one scrolling column; a wheel turn moves it at once,
        while a click on the category menu animates the scroll. The menu is the fallback.
        """
        opened = False
        previous: float | None = None
        for _ in range(MAX_SCROLLS + 2):
            found = await locate()
            if not found.get("found") or (previous is not None and found["rect"]["y"] == previous):
                if opened:
                    raise OracleDivergenceError(f"{what} is not in the {category} palette")
                async for gesture in self._open_category(category):
                    yield gesture
                opened, previous = True, None
                continue
            if found.get("visible") and found.get("grab", True):
                return
            view, rect = found["flyout"], found["rect"]
            delta = max(-MAX_WHEEL, min(MAX_WHEEL, rect["y"] - view["y"] - FLYOUT_MARGIN))
            previous = rect["y"]
            yield scroll(delta, 0.0, *centre(view))
            await self._wait("flyoutSettled", what="the palette to stop scrolling")
        raise OracleDivergenceError(f"{what} stays out of view in the palette")

    async def _open_category(self, category: str) -> AsyncIterator[PrimitiveAction]:
        layout = await self._layout()
        items = [item for item in layout["categories"] if item["name"] == category]
        if not items:
            raise OracleDivergenceError(f"the category menu has no {category!r}")
        yield click(*centre(items[0]["rect"]))
        await self._wait("flyoutSettled", what=f"the palette to scroll to {category}")

    async def _palette_block(self, opcode: str, variable: str | None) -> dict[str, Any]:
        found = _dict(await self._editor_call("geometryFlyoutBlock", {"opcode": opcode, "variableName": variable}))
        if not (found.get("found") and found.get("grab")):
            raise OracleDivergenceError(f"{opcode} is no longer grabbable in the palette")
        return found

    async def _match_new_fields(self, step: PlannedStep, live_id: str) -> AsyncIterator[PrimitiveAction]:
        """Give a new block the dropdown choices the dry run gave it (e.g. the variable of a set block)."""
        wanted = step.new_fields or {}
        have = _dict(await self._editor_call("geometryBlockFields", {"id": live_id}))
        for kind in ("fields", "inputs"):
            for name, value in (wanted.get(kind) or {}).items():
                if (have.get(kind) or {}).get(name) != value:
                    async for gesture in self._set_value(live_id, name, str(value), kind, step):
                        yield gesture

    async def _anchor(self, step: PlannedStep) -> Callable[[], Awaitable[Point | None]] | None:
        """Where the next connection involving the new block will happen, if its partner is on the page."""
        new_id = f"new:{step.data['blockId']}"
        for later in self._plan[step.number :]:
            if later.action.api != "connect_blocks":
                continue
            source, target = later.blocks.get("sourceBlockIndex"), later.blocks.get("targetBlockIndex")
            if new_id not in (source, target):
                continue
            partner = target if source == new_id else source
            if partner is None or partner not in self._live:
                return None
            placement = later.action.args.get("placement")
            locate = self._locator(self._live[partner], placement if source == new_id else None)
            return locate if await locate() is not None else None
        return None

    def _locator(self, block: str, placement: object) -> Callable[[], Awaitable[Point | None]]:
        """Where ``block`` is now: the connection ``placement`` aims at on it, or its top-left corner."""

        async def locate() -> Point | None:
            try:
                info = await self._block(block)
            except BridgeError:
                return None
            point = _target_point(info, placement) if isinstance(placement, dict) else None
            return point if point is not None else (info["rect"]["x"], info["rect"]["y"])

        return locate

    # ---------- connecting ----------

    async def _connect_blocks(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        source = self._live_id(step, "sourceBlockIndex")
        target = self._live_id(step, "targetBlockIndex")
        placement = step.action.args.get("placement")
        if not isinstance(placement, dict):
            raise OracleDivergenceError(f"{step.describe()}: placement must be an object")
        info = await self._block(source)
        shape = info["shape"]
        # A GUI drag takes the block and everything under it; the composite API moves a non-hat alone.
        if not shape["hat"] and not shape["reporter"] and info["nextBlock"]:
            async for gesture in self._isolate(info, step):
                yield gesture
        attached = (await self._block(target))["attachment"] is not None
        local, remote = connection_pair(placement, attached)
        async for gesture in self._drag_connection(source, local, target, remote, step):
            yield gesture

    async def _isolate(self, info: dict[str, Any], step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        """Leave the block without its tail, the tail taking its place (the composite API's healing)."""
        tail = str(info["nextBlock"])
        block = str(info["id"])
        attachment = info["attachment"]
        if attachment is None:
            async for gesture in self._drag_to_free_space(tail, step):
                yield gesture
        else:
            # The block and its tail go to empty space, then the tail goes back where the block hung.
            async for gesture in self._drag_to_free_space(block, step):
                yield gesture
            hook = "next" if attachment["input"] is None else f"input:{attachment['input']}"
            async for gesture in self._drag_connection(tail, "previous", str(attachment["parent"]), hook, step):
                yield gesture
        if (await self._block(block))["nextBlock"] is not None:
            raise OracleDivergenceError(f"{step.describe()}: could not take block {block} out of its stack alone")

    async def _drag_connection(
        self, moving: str, local: str, target: str, remote: str, step: PlannedStep
    ) -> AsyncIterator[PrimitiveAction]:
        """Drag ``moving`` so that its connection ``local`` snaps to connection ``remote`` of ``target``.

        The page replays Blockly's choice of connection along the straight mouse path; when another
        connection would be chosen on the way, the block first moves to a free spot with a clean path.
        """
        args = {"moving": moving, "local": local, "target": target, "remote": remote, "steps": DRAG_STEPS}
        staged = False
        for _ in range(MAX_SCROLLS + 2):
            plan = _dict(await self._editor_call("geometryPlanDrag", args))
            grab, end = _point(plan["grab"]), _point(plan["end"])
            if grab is None:
                async for gesture in self._reach(moving, step):
                    yield gesture
                continue
            if not plan["endVisible"]:
                area = (await self._layout())["safeArea"]
                async for gesture in self._scroll_towards(
                    [_point(plan["reference"]) or (0.0, 0.0), end or (0.0, 0.0)], area
                ):
                    yield gesture
                continue
            if plan["clean"]:
                yield drag(grab, end)
                await self._wait("quiet", what="the drop to settle")
                return
            staging = plan.get("staging")
            if staged or not isinstance(staging, dict):
                raise OracleDivergenceError(
                    f"{step.describe()}: no clean path to connect {local} of {moving} to {remote} of {target}: "
                    f"{plan['reason']}"
                )
            yield drag(grab, _point(staging["end"]) or grab)
            await self._wait("quiet", what="the block to settle on its staging spot")
            staged = True
        raise OracleDivergenceError(
            f"{step.describe()}: cannot show {moving} and its destination on {target} in the workspace at once"
        )

    async def _drag_to_free_space(self, block: str, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        async for gesture in self._reach(block, step):
            yield gesture
        info = await self._block(block)
        grab = _point(info["grab"])
        if grab is None:
            raise OracleDivergenceError(f"{step.describe()}: block {block} cannot be grabbed")
        rect = info["rect"]
        # A top-level block leaves its own place free; one inside a script must keep off the whole script.
        ignore = [block] if info["root"] == block else []
        spot = await self._free_spot(rect["width"], rect["height"], (rect["x"], rect["y"] + rect["height"]), ignore)
        for _ in range(ROOM_SCROLLS):
            if spot is not None:
                break
            async for gesture in self._scroll_for_room():
                yield gesture
            info = await self._block(block)
            grab, rect = _point(info["grab"]), info["rect"]
            if grab is None:
                break  # scrolled out of reach: give up below
            near = (rect["x"], rect["y"] + rect["height"])
            spot = await self._free_spot(rect["width"], rect["height"], near, ignore)
        if spot is None or grab is None:
            raise OracleDivergenceError(
                f"{step.describe()}: no empty part of the visible workspace can take the blocks"
            )
        yield drag(grab, (spot[0] + grab[0] - rect["x"], spot[1] + grab[1] - rect["y"]))
        await self._wait("quiet", what="the drop to settle")

    async def _reach(self, block: str, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        """Make a point of the block's body grabbable: scroll to it, or clean up scripts covering it."""
        cleaned = False
        for _ in range(MAX_SCROLLS + 1):
            info = await self._block(block)
            if info["grab"] is not None:
                return
            middle = centre(info["rect"])
            area = (await self._layout())["safeArea"]
            if _inside(area, middle):
                if cleaned:
                    break
                async for gesture in self._clean_up(step):
                    yield gesture
                cleaned = True
            else:
                async for gesture in self._scroll_towards([middle], area):
                    yield gesture
        raise OracleDivergenceError(f"{step.describe()}: no part of block {block} can be grabbed")

    async def _clean_up(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        """Right-click the workspace background, choose "Clean up Blocks": scripts stop overlapping."""
        spot = await self._free_spot(8, 8, None)
        if spot is None:
            raise OracleDivergenceError(f"{step.describe()}: no empty workspace background to right-click")
        yield PrimitiveAction(api="click", args={"x": spot[0] + 4, "y": spot[1] + 4, "button": "right"})
        await self._wait("menuOpen", what="the workspace context menu")
        items = [item for item in _dict(await self._editor_call("geometryMenu"))["items"] if item["text"] == CLEAN_UP]
        if not items or not items[0]["visible"]:
            raise OracleDivergenceError(f"{step.describe()}: the workspace context menu has no visible {CLEAN_UP!r}")
        yield click(*centre(items[0]["rect"]))
        await self._wait("menuClosed", what="the context menu to close")
        await self._wait("quiet", what="the scripts to be cleaned up")

    async def _detach_blocks(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        if step.data.get("detached") is False:
            return  # already the first block of its script
        async for gesture in self._drag_to_free_space(self._live_id(step, "blockIndex"), step):
            yield gesture

    async def _delete_block(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        block = self._live_id(step, "blockIndex")
        async for gesture in self._reach(block, step):
            yield gesture
        info = await self._block(block)
        grab = _point(info["grab"])
        if grab is None:
            raise OracleDivergenceError(f"{step.describe()}: block {block} cannot be grabbed")
        palette = (await self._layout())["flyout"]
        yield drag(grab, centre(palette))  # dropped on the palette, blocks are deleted
        await self._wait("quiet", what="the deletion to settle")

    # ---------- fields ----------

    async def _set_block_field(self, step: PlannedStep) -> AsyncIterator[PrimitiveAction]:
        block = self._live_id(step, "blockIndex")
        name = str(step.action.args["fieldName"])
        kind = "fields" if "field" in step.data else "inputs"
        value = str(step.data["value"])
        have = _dict(await self._editor_call("geometryBlockFields", {"id": block}))
        if (have.get(kind) or {}).get(name) == value:
            return
        async for gesture in self._set_value(block, name, value, kind, step):
            yield gesture

    async def _set_value(
        self, block: str, name: str, value: str, kind: str, step: PlannedStep
    ) -> AsyncIterator[PrimitiveAction]:
        """Click a field (or an input's value) and type or choose ``value`` as the VM stores it."""
        what = f"{step.describe()}: field {name} of block {block}"

        async def field_points() -> list[Point]:
            return _rect_corners((await self._field(block, name))["rect"])

        async for gesture in self._scroll_into_view(field_points, what):
            yield gesture
        field = await self._field(block, name)
        yield click(*centre(field["rect"]))
        if field["kind"] == "text":
            await self._wait("textEditorOpen", what=f"the text editor of {name}")
            async for gesture in self._type_into_editor(value, what):
                yield gesture
            yield PrimitiveAction(api="key", args={"key": "Enter"})
            await self._wait("textEditorClosed", what=f"the text editor of {name} to close")
        else:
            async for gesture in self._choose(field, value, what):
                yield gesture
        await self._wait("quiet", what=f"{name} to settle")
        result = await self._wait_result("blockValue", {"id": block, "kind": kind, "name": name, "value": value})
        if not result.get("ok"):
            raise OracleDivergenceError(f"{what} holds {result.get('value')!r}, not {value!r}")

    async def _type_into_editor(self, value: str, what: str) -> AsyncIterator[PrimitiveAction]:
        """Replace the open text editor's text; checked, since a field may refuse a keystroke."""
        seen: list[str | None] = []
        for _ in range(TYPE_ATTEMPTS):
            yield PrimitiveAction(api="hotkey", args={"keys": ["ctrl", "a"]})
            if value:
                yield PrimitiveAction(api="type", args={"text": value})
            else:
                yield PrimitiveAction(api="key", args={"key": "Backspace"})
            editor = _dict(await self._editor_call("geometryTextEditor"))
            if editor["value"] == value:
                return
            seen.append(editor["value"])
        raise OracleDivergenceError(f"{what}: typing {value!r} left {seen} in the text editor")

    async def _choose(self, field: dict[str, Any], value: str, what: str) -> AsyncIterator[PrimitiveAction]:
        await self._wait("menuOpen", what="the dropdown to open")
        if field["name"] in VARIABLE_FIELDS:
            text = value
        else:
            options = field.get("options") or []
            text = next((o["text"] for o in options if o["value"] == value), value)
        for _ in range(MAX_SCROLLS * 3):
            menu = _dict(await self._editor_call("geometryMenu"))
            items = [item for item in menu["items"] if item["text"] == text]
            if not items and field["name"] == "BROADCAST_OPTION":
                items = [item for item in menu["items"] if item["text"] == NEW_MESSAGE]
            if not items:
                offered = [item["text"] for item in menu["items"]]
                raise OracleDivergenceError(f"{what}: the dropdown offers no {text!r} (items: {offered})")
            item = items[0]
            if item["visible"]:
                yield click(*centre(item["rect"]))
                await self._wait("menuClosed", what="the dropdown to close")
                if item["text"] == NEW_MESSAGE and text != NEW_MESSAGE:
                    async for gesture in self._fill_prompt(text):
                        yield gesture
                return
            box = menu["rect"]
            delta = centre(item["rect"])[1] - centre(box)[1]
            yield scroll(delta, 0.0, *centre(box))
            await self._wait("menuOpen", what="the dropdown to stop scrolling")
        raise OracleDivergenceError(f"{what}: the dropdown item {text!r} stays out of view")

    # ---------- scrolling and space ----------

    async def _scroll_into_view(
        self, locate: Callable[[], Awaitable[list[Point]]], what: str
    ) -> AsyncIterator[PrimitiveAction]:
        for _ in range(MAX_SCROLLS):
            points = await locate()
            area = (await self._layout())["safeArea"]
            if all(_inside(area, p) for p in points):
                return
            async for gesture in self._scroll_towards(points, area):
                yield gesture
        if not all(_inside((await self._layout())["safeArea"], p) for p in await locate()):
            raise OracleDivergenceError(f"{what}: cannot scroll it into view")

    async def _scroll_towards(self, points: list[Point], area: dict[str, float]) -> AsyncIterator[PrimitiveAction]:
        """Wheel the workspace so that the box around ``points`` is centred in ``area`` (if it fits)."""
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        if max(xs) - min(xs) > area["width"] or max(ys) - min(ys) > area["height"]:
            raise OracleDivergenceError(
                f"points spanning {_fmt((max(xs) - min(xs), max(ys) - min(ys)))} px do not fit in the workspace at once"
            )
        middle = centre(area)
        dx = (min(xs) + max(xs)) / 2 - middle[0] if min(xs) < area["x"] or max(xs) > area["x"] + area["width"] else 0.0
        dy = (min(ys) + max(ys)) / 2 - middle[1] if min(ys) < area["y"] or max(ys) > area["y"] + area["height"] else 0.0
        if abs(dx) < 1 and abs(dy) < 1:
            return
        yield scroll(dy, dx, *middle)
        await self._wait("quiet", what="the workspace to stop scrolling")

    async def _scroll_for_room(self) -> AsyncIterator[PrimitiveAction]:
        """Wheel the workspace down by half a view: there is empty space under the scripts."""
        area = (await self._layout())["safeArea"]
        yield scroll(area["height"] / 2, 0.0, *centre(area))
        await self._wait("quiet", what="the workspace to stop scrolling")

    async def _free_spot(
        self, width: float, height: float, near: Point | None, ignore: list[str] | None = None
    ) -> Point | None:
        args: dict[str, Any] = {"width": width, "height": height, "ignore": ignore or []}
        if near is not None:
            args["near"] = {"x": near[0], "y": near[1]}
        spot = _dict(await self._editor_call("geometryFreeSpot", args)).get("spot")
        return (float(spot["x"]), float(spot["y"])) if isinstance(spot, dict) else None

    # ---------- reads ----------

    def _live_id(self, step: PlannedStep, name: str) -> str:
        identity = step.blocks.get(name)
        if identity is None:
            raise OracleDivergenceError(f"{step.describe()}: {name} denoted no block in the dry run")
        if identity not in self._live:
            raise OracleDivergenceError(f"{step.describe()}: the GUI run has no block for {identity}")
        return self._live[identity]

    def _require_editor(self) -> Editor:
        if self._editor is None:
            raise RuntimeError("PrimitiveOracle.begin(editor) must run first")
        return self._editor

    async def _editor_call(
        self, name: str, args: dict[str, Any] | None = None, timeout_ms: int | None = None
    ) -> JsonValue:
        if timeout_ms is not None and args is not None:
            args = {**args, "timeoutMs": timeout_ms}
        return await self._require_editor().call(name, args)

    async def _layout(self) -> dict[str, Any]:
        return _dict(await self._editor_call("geometryLayout"))

    async def _block(self, block_id: str) -> dict[str, Any]:
        return _dict(await self._editor_call("geometryBlock", {"id": block_id}))

    async def _field(self, block_id: str, name: str) -> dict[str, Any]:
        field = _dict(await self._editor_call("geometryField", {"id": block_id, "name": name}))
        if field.get("rect") is None:
            raise OracleDivergenceError(f"field {name} of block {block_id} is not drawn")
        return field

    async def _top_blocks(self) -> dict[str, Any]:
        return _dict(await self._editor_call("geometryTopBlocks"))

    async def _paths(self) -> dict[str, dict[str, str]]:
        return _dict(_dict(await self._editor_call("geometryBlockPaths"))["paths"])

    async def _snapshot(self) -> str:
        return str(_dict(await self._editor_call("geometrySnapshot"))["text"])

    async def _wait_result(
        self, until: str, args: dict[str, Any] | None = None, timeout_ms: int = WAIT_MS
    ) -> dict[str, Any]:
        return _dict(
            await self._editor_call("geometryWait", {"until": until, "args": args or {}, "timeoutMs": timeout_ms})
        )

    async def _wait(
        self, until: str, args: dict[str, Any] | None = None, *, what: str, timeout_ms: int = WAIT_MS
    ) -> None:
        result = await self._wait_result(until, args, timeout_ms)
        if not result.get("ok"):
            raise OracleDivergenceError(
                f"gave up waiting for {what} after {timeout_ms / 1000:g} s ({until}: {result.get('value')!r})"
            )


# ---------- gestures ----------


def click(x: float, y: float) -> PrimitiveAction:
    return PrimitiveAction(api="click", args={"x": round(x, 2), "y": round(y, 2)})


def drag(start: Point, end: Point) -> PrimitiveAction:
    return PrimitiveAction(
        api="drag_and_drop",
        args={
            "start_x": round(start[0], 2),
            "start_y": round(start[1], 2),
            "end_x": round(end[0], 2),
            "end_y": round(end[1], 2),
            "duration": DRAG_DURATION,
        },
    )


def scroll(dy: float, dx: float, x: float, y: float) -> PrimitiveAction:
    """A wheel turn at (x, y) that moves the content under it up by ``dy`` and left by ``dx`` pixels."""
    if abs(dy) >= abs(dx):
        direction, amount = ("down" if dy > 0 else "up"), abs(dy)
    else:
        direction, amount = ("right" if dx > 0 else "left"), abs(dx)
    return PrimitiveAction(
        api="scroll", args={"direction": direction, "amount": max(1, round(amount)), "x": round(x, 2), "y": round(y, 2)}
    )


# ---------- geometry helpers ----------


def centre(rect: dict[str, float]) -> Point:
    return rect["x"] + rect["width"] / 2, rect["y"] + rect["height"] / 2


def _point(value: object) -> Point | None:
    if (
        isinstance(value, dict)
        and isinstance(value.get("x"), (int, float))
        and isinstance(value.get("y"), (int, float))
    ):
        return float(value["x"]), float(value["y"])
    return None


def _inside(area: dict[str, float], point: Point) -> bool:
    return area["x"] <= point[0] <= area["x"] + area["width"] and area["y"] <= point[1] <= area["y"] + area["height"]


def _rect_corners(rect: dict[str, float]) -> list[Point]:
    return [(rect["x"], rect["y"]), (rect["x"] + rect["width"], rect["y"] + rect["height"])]


async def _points(point: Awaitable[Point | None]) -> list[Point]:
    found = await point
    return [found] if found is not None else []


def connection_pair(placement: dict[str, Any], target_attached: bool) -> tuple[str, str]:
    """(connection of the dragged block, connection of the destination) that a placement joins.

    ``target_attached``: the destination hangs under another block (matters for stack_before).
    """
    kind, name = placement.get("kind"), placement.get("inputName")
    if kind == "stack_after":
        return "previous", "next"
    if kind == "statement_into":
        return "previous", f"input:{name}"
    if kind == "value_into":
        return "output", f"input:{name}"
    if kind == "stack_before":
        # Inside a script the block goes where the destination hangs (Blockly inserts it);
        # on top of a script the end of the dragged stack meets the destination's top.
        return ("previous", "parent") if target_attached else ("lastNext", "previous")
    if kind == "wrap" and not target_attached:
        return "input:SUBSTACK", "previous"
    raise OracleDivergenceError(f"placement {placement} is not mapped to gestures")


def _target_point(dst: dict[str, Any], placement: dict[str, Any]) -> Point | None:
    """The connection on the destination block that the dragged block must meet."""
    kind = placement.get("kind")
    if kind == "stack_after":
        return _point(dst["next"])
    if kind in ("statement_into", "value_into"):
        return _point(dst["inputs"].get(str(placement.get("inputName"))))
    if kind in ("stack_before", "wrap"):
        return _point(dst["previous"])
    return None


def _scope_option(scope: str) -> str:
    return "For all sprites" if scope == "all" else "For this sprite only"


def _fmt(point: Point) -> str:
    return f"({point[0]:.0f}, {point[1]:.0f})"


def _dict(value: JsonValue) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise OracleDivergenceError(f"the page answered {type(value).__name__}, expected an object")
    return value


def _ids(value: JsonValue) -> list[str | None]:
    ids = _dict(value).get("ids")
    if not isinstance(ids, list):
        raise OracleDivergenceError("compositeBlockIds answered no id list")
    return [str(i) if i is not None else None for i in ids]


# ---------- describing a divergence ----------


def describe_difference(expected: dict[str, Any], actual: object) -> str:
    """What differs between two geometrySnapshot states, in a few readable lines."""
    if not isinstance(actual, dict):
        return f"no snapshot could be read (got {actual!r})"
    problems: list[str] = []
    if expected.get("editingTarget") != actual.get("editingTarget"):
        problems.append(f"editing {actual.get('editingTarget')!r}, expected {expected.get('editingTarget')!r}")
    mine = {t["name"]: t for t in actual.get("targets", [])}
    for target in expected.get("targets", []):
        name = target["name"]
        have = mine.get(name)
        if have is None:
            problems.append(f"target {name!r} is missing")
            continue
        if have["variables"] != target["variables"]:
            problems.append(f"{name} variables {have['variables']}, expected {target['variables']}")
        missing = [s for s in target["scripts"] if s not in have["scripts"]]
        extra = [s for s in have["scripts"] if s not in target["scripts"]]
        for script in missing:
            problems.append(f"{name} lacks script {script_text(json.loads(script))}")
        for script in extra:
            problems.append(f"{name} has unexpected script {script_text(json.loads(script))}")
    return "; ".join(problems) or "the states differ"


def script_text(chain: list[dict[str, Any]]) -> str:
    """A compact one-line rendering of a snapshot script: ``opcode[FIELD=v](INPUT: ...) > next``."""
    parts = []
    for block in chain:
        text = block["opcode"]
        if block["fields"]:
            text += "[" + ",".join(f"{k}={v}" for k, v in block["fields"].items()) + "]"
        inputs = [f"{k}: {script_text(v)}" for k, v in block["inputs"].items()]
        if inputs:
            text += "(" + "; ".join(inputs) + ")"
        parts.append(text)
    return " > ".join(parts)
