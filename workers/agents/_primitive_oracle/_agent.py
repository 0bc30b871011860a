"""``PrimitiveOracle``: the dry run at ``begin``, then one gesture per ``act``, each step checked."""

from __future__ import annotations

from collections.abc import AsyncIterator, Callable

from workers.agents._primitive_oracle._divergence import OracleDivergenceError
from workers.agents._primitive_oracle._fields import set_block_field
from workers.agents._primitive_oracle._moves import connect_blocks, delete_block, detach_blocks
from workers.agents._primitive_oracle._page import Page
from workers.agents._primitive_oracle._palette import add_block, add_variable
from workers.agents._primitive_oracle._plan import PlannedStep, Run, dry_run
from workers.agents._primitive_oracle._targets import select_sprite, select_stage
from workers.contract import Action, CompositeAction, Done, PrimitiveAction
from workers.editor import Editor

Handler = Callable[[Run, PlannedStep], AsyncIterator[PrimitiveAction]]

HANDLERS: dict[str, Handler] = {
    "select_sprite": select_sprite,
    "select_stage": select_stage,
    "add_variable": add_variable,
    "add_list": add_variable,
    "add_block": add_block,
    "connect_blocks": connect_blocks,
    "detach_blocks": detach_blocks,
    "set_block_field": set_block_field,
    "delete_block": delete_block,
}
"""The gestures of each composite api the golden trajectories use."""

RELOAD_WAIT_MS = 10_000


class PrimitiveOracle:
    """Scripted primitive-mode agent: the golden trajectory as gestures, one per ``act``."""

    observes = False

    def __init__(self, initial_project: bytes, trajectory: list[CompositeAction]) -> None:
        self._initial = initial_project
        self._trajectory = list(trajectory)
        self._plan: list[PlannedStep] = []
        self._initial_snapshot = ""
        self._gestures: AsyncIterator[PrimitiveAction] | None = None
        self.gesture_count = 0
        """Gestures handed out so far."""

    @property
    def plan(self) -> list[PlannedStep]:
        return list(self._plan)

    async def begin(self, editor: Editor) -> None:
        """Dry-run the trajectory on the loaded project, then reload it for the real run."""
        page = Page(editor)
        before = await page.snapshot()
        paths = await page.paths()
        self._initial_snapshot = before.text
        try:
            self._plan = await dry_run(editor, page, self._trajectory, before.state.editing_target, paths)
        finally:
            await editor.load_project(self._initial)
            await editor.set_stage_size("small")
        await page.wait("quiet", timeout_ms=RELOAD_WAIT_MS, what="the reloaded project to be drawn")
        if (await page.snapshot()).text != before.text:
            raise OracleDivergenceError("reloading the initial project did not restore its scripts")
        # Ids of compact blocks (variable reporters in inputs) are new on every load: map by path.
        reloaded = {f"path:{path}": block for target in (await page.paths()).values() for block, path in target.items()}
        if set(reloaded) != {f"path:{path}" for target in paths.values() for path in target.values()}:
            raise OracleDivergenceError("reloading the initial project did not restore its blocks")
        self._gestures = self._solve(Run(page, self._plan, reloaded))

    async def act(self, observation: object | None) -> Action:
        if self._gestures is None:
            raise RuntimeError("PrimitiveOracle.begin(editor) must run before act()")
        try:
            gesture = await anext(self._gestures)
        except StopAsyncIteration:
            return Done()
        self.gesture_count += 1
        return gesture

    async def _solve(self, run: Run) -> AsyncIterator[PrimitiveAction]:
        """Every step's gestures, after the editor settled; after each, the state the dry run reached."""
        for step in self._plan:
            handler = HANDLERS.get(step.action.api)
            if handler is None:
                raise OracleDivergenceError(f"{step.describe()}: no gestures are known for {step.action.api}")
            await run.page.wait("quiet", what=f"the editor to settle before {step.describe()}")
            async for gesture in handler(run, step):
                yield gesture
            await run.page.expect_state(step.snapshot, f"after {step.describe()}")
        expected = self._plan[-1].snapshot if self._plan else self._initial_snapshot
        await run.page.expect_state(expected, "at the end of the run")
