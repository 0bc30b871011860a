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
    of page time before the first observation, before each action and after it, and none in between."""

    def __init__(self, editor: Editor, clock: EpisodeClock, *, filmed: bool = False) -> None:
        """``filmed``: the page is recorded as a video, so the stage is drawn during gestures too."""
        self.editor = editor
        self.clock = clock
        self.virtual = clock.mode == "virtual"
        self.filmed = filmed
        self.elapsed_ms = 0
        """Page time moved so far on the virtual clock (the episode's time, recorded with each step)."""

    async def _advance(self, ms: int, *, draw: bool = True) -> None:
        await self.editor.advance_clock(ms, draw=draw)
        self.elapsed_ms += ms

    async def pass_time(self, ms: float) -> None:
        """Page time during an action (a drag's moves); only on the virtual clock. The stage is not drawn
        meanwhile unless filmed: nobody looks at it before ``after_action`` draws it, and a drawn stage
        made each of a drag's moves cost the browser a third more (the VM runs its frames either way)."""
        await self._advance(round(ms), draw=self.filmed)

    async def start(self) -> None:
        if self.virtual:
            await self.editor.start_episode_clock(self.clock)
            await self._advance(self.clock.start_ms)
            await self.editor.redraw_panels()

    async def before_action(self) -> None:
        if self.virtual:
            await self._advance(ACTION_LEAD_MS)

    async def after_action(self) -> None:
        if self.virtual:
            await self._advance(self.clock.step_ms)
