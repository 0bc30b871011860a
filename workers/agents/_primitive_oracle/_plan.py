"""The plan: the golden trajectory replayed through the composite API (the *dry run*), step by step.

The trajectory's index arguments depend on block positions, which differ in a GUI run; the dry
run learns which block each index denotes (by a structural path in the initial project, or as a
block a step added) and the semantic project state after every step, for the real run to aim at
and check against.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

from workers import composite
from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._page import Page
from workers.agents._primitive_oracle._state import BlockFields
from workers.contract import CompositeAction
from workers.editor import Editor

INDEX_ARGS = ("sourceBlockIndex", "targetBlockIndex", "blockIndex")


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
    new_fields: BlockFields | None
    """For add_block: the VM fields and input values the dry run gave the new block."""
    snapshot: str
    """The semantic project state after the step (geometrySnapshot's JSON text)."""

    def describe(self) -> str:
        return f"step {self.number} {self.action.api} {json.dumps(self.action.args, sort_keys=True)}"


@dataclass
class Run:
    """What the real run's step handlers share: the page, the plan, and where planned blocks are now."""

    page: Page
    plan: list[PlannedStep]
    live: dict[str, str]
    """Block identity (see ``PlannedStep.blocks``) -> id of the block in the GUI run."""

    def live_id(self, step: PlannedStep, name: str) -> str:
        """The GUI run's id of the block the index argument ``name`` of ``step`` denotes."""
        identity = step.blocks.get(name)
        if identity is None:
            raise OracleDivergenceError(f"{step.describe()}: {name} denoted no block in the dry run")
        if identity not in self.live:
            raise OracleDivergenceError(f"{step.describe()}: the GUI run has no block for {identity}")
        return self.live[identity]


async def dry_run(
    editor: Editor,
    page: Page,
    trajectory: list[CompositeAction],
    editing: str | None,
    paths: dict[str, dict[str, str]],
) -> list[PlannedStep]:
    """Replay ``trajectory`` on the loaded project (``editing``: its editing target; ``paths``: its blocks')."""
    plan: list[PlannedStep] = []
    for number, action in enumerate(trajectory, start=1):
        blocks: dict[str, str] = {}
        if any(isinstance(action.args.get(name), int) for name in INDEX_ARGS):
            ids = await page.block_ids()
            initial = paths.get(editing, {}) if editing is not None else {}
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
            new_fields = await page.block_fields(str(data["blockId"]))
        snapshot = await page.snapshot()
        editing = snapshot.state.editing_target
        plan.append(PlannedStep(number, action, blocks, dict(data), new_fields, snapshot.text))
    return plan
