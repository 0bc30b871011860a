"""How page time passes in an agent's episode: the page clock advanced around each action on the virtual clock."""

from __future__ import annotations

from workers.contract import EpisodeClock
from workers.editor import Editor

ACTION_LEAD_MS = 50
"""Virtual page time before each action: the timers the page set meanwhile (an observation, a
privileged agent reading the page) come due first, as they would have while a user reached for the
mouse; e.g. Blockly makes a block it has just drawn a drop target 1 ms later."""


class Pace:
    """The agent page's time: nothing to do on the real clock; on the virtual clock, a fixed amount
    of page time before the first observation, before each action and after it, and none in between.

    The VM runs its frames whenever page time passes, but the stage's picture is drawn only where
    somebody may look at it: after an advance that ends where the agent looks (``stage_seen``: its
    screenshots, or a privileged agent's own look at the page), and throughout when the page is
    ``filmed``. Nothing else reads the drawn stage (touching, colour sensing and the pen do not), so
    what an agent is shown is the same either way, while a drawn frame of the software-WebGL stage
    cost the browser more than a composite step's own work (measured: 45-55 ms against 20-23 ms)."""

    def __init__(self, editor: Editor, clock: EpisodeClock, *, stage_seen: bool = True, filmed: bool = False) -> None:
        self.editor = editor
        self.clock = clock
        self.virtual = clock.mode == "virtual"
        self.stage_seen = stage_seen
        self.filmed = filmed
        self.elapsed_ms = 0
        """Page time moved so far on the virtual clock (the episode's time, recorded with each step)."""

    async def _advance(self, ms: int, *, looked_at: bool) -> None:
        """``looked_at``: the agent may look at the page once this advance is over."""
        await self.editor.advance_clock(ms, draw=self.filmed or (looked_at and self.stage_seen))
        self.elapsed_ms += ms

    async def pass_time(self, ms: float) -> None:
        """Page time during an action (a drag's moves); only on the virtual clock."""
        await self._advance(round(ms), looked_at=False)

    async def start(self) -> None:
        if self.virtual:
            await self.editor.start_episode_clock(self.clock)
            await self._advance(self.clock.start_ms, looked_at=True)
            await self.editor.redraw_panels()

    async def before_action(self) -> None:
        if self.virtual:
            await self._advance(ACTION_LEAD_MS, looked_at=False)  # the action follows at once

    async def after_action(self) -> None:
        if self.virtual:
            await self._advance(self.clock.step_ms, looked_at=True)
