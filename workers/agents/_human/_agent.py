"""``HumanAgent``: a person works on the task in our editor, through a page that shows it live and relays
their input; what they do is recorded as the steps of the primitive action schema.

The editor is every agent's: our Chromium, confined, with the task's initial project. The person's gestures
happen in it as they make them (``acts_live``: the harness records them and does not perform them again);
each ``act`` hands the runner the next completed gesture, so the runner observes (screenshot, element list)
between them and the trajectory reads like a model's. Submit ends the episode with ``done``, Give up with
``failed``; a page closed for longer than ``RECONNECT_GRACE_S`` without either is ``participant_left``.
"""

from __future__ import annotations

import asyncio
import contextlib
import logging
import os
import time
from collections import deque
from typing import ClassVar

from pydantic import BaseModel, ConfigDict, Field

from workers.agent_api import AgentBase, EpisodeEnd, StepResult, TaskContext
from workers.agents._human._events import Decision, Ended, PageMessage, Progress, TaskShown
from workers.agents._human._recorder import GestureRecorder
from workers.agents._human._relay import InputRelay
from workers.agents._human._server import PageServer
from workers.contract import Action, Done, EditorCrashedError, Failed, Mode, Observation, ParticipantLeftError
from workers.editor import Screencast

log = logging.getLogger(__name__)

PORT_VARIABLE = "SCRATCHWORLD_HUMAN_PORT"
DEFAULT_PORT = 8765
"""Where the page listens unless ``SCRATCHWORLD_HUMAN_PORT`` says otherwise: fixed, so an SSH tunnel can be set
up before the job starts (human jobs run one at a time, so one port serves a whole sweep)."""

LIVE_QUALITY = 70
"""JPEG quality of the live view's frames (lighter than a video's over an SSH tunnel)."""

RECONNECT_GRACE_S = 30.0
"""How long a closed page may stay closed (a reload, a dropped tunnel) before the episode ends as an error."""


def human_port() -> int:
    """The port from ``SCRATCHWORLD_HUMAN_PORT`` (0: any free one), else ``DEFAULT_PORT``."""
    given = os.environ.get(PORT_VARIABLE, "").strip()
    if not given:
        return DEFAULT_PORT
    if not given.isdigit() or int(given) > 65535:
        raise ValueError(f"{PORT_VARIABLE}={given!r} is not a port number")
    return int(given)


class HumanParams(BaseModel):
    """Who is at the screen: part of the job's identity, so two people on one task are two jobs."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    participant: str = Field(min_length=1, max_length=64, pattern=r"^[A-Za-z0-9][A-Za-z0-9._-]*$")


class HumanAgent(AgentBase):
    """A person at the page ``url`` (see the module's docstring)."""

    Params: ClassVar[type[BaseModel]] = HumanParams
    observes = True
    acts_live = True
    real_time = True
    exclusive = True
    modes: ClassVar[tuple[Mode, ...]] = ("primitive", "composite")

    def __init__(self, params: BaseModel | None = None) -> None:
        super().__init__(params)
        self.port = human_port()
        self.reconnect_grace_s = RECONNECT_GRACE_S
        self.server: PageServer | None = None
        self.opened = asyncio.Event()
        """Set once the page is served (``server.url``)."""

        self._actions: deque[Action] = deque()
        self._recorder = GestureRecorder()
        self._relay: InputRelay | None = None
        self._screencast: Screencast | None = None
        self._decision: Done | Failed | None = None
        self._left_at: float | None = None
        self._changed = asyncio.Event()
        self._steps = 0

    async def start(self, context: TaskContext) -> None:
        await super().start(context)
        page = context.privileges.editor.page
        participant = getattr(self.params, "participant", "")
        self.server = PageServer(self.port, self._message, self._presence)
        self.server.greeting = TaskShown(
            task_id=context.task_id,
            instruction=context.instruction,
            mode=context.mode,
            max_steps=context.max_steps,
            participant=participant,
            started_at=time.time(),
            viewport=dict(page.viewport_size or {"width": 1280, "height": 720}),
        )
        self._relay = InputRelay(page)
        self._screencast = Screencast(page, lambda frame: self.server.send_frame(frame.jpeg), quality=LIVE_QUALITY)
        try:
            await self.server.start()
            await self._screencast.start()
        except BaseException:
            await self._close()
            raise
        self._relay.start()
        log.info("task %s for %s: open %s", context.task_id, participant, self.server.url)
        self.opened.set()

    def _message(self, message: PageMessage) -> None:
        if isinstance(message, Decision):
            if self._decision is None:
                self._decision = Done() if message.type == "submit" else Failed(reason="the participant gave up")
        elif self._decision is None and self._relay is not None:  # input after a decision changes nothing
            self._relay.put(message)
            self._actions.extend(self._recorder.feed(message, time.monotonic()))
        self._changed.set()

    def _presence(self, pages: int) -> None:
        self._left_at = None if pages else time.monotonic()
        self._changed.set()

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        if self.server is None or self._relay is None:
            raise RuntimeError("HumanAgent.start must run before act")
        self.server.send(Progress(steps=self._steps, ready=True))
        while True:
            now = time.monotonic()
            self._actions.extend(self._recorder.due(now))
            if self._relay.failure is not None:
                raise EditorCrashedError(f"the editor stopped taking the person's input: {self._relay.failure.message}")
            if not self._actions and self._decision is not None:
                self._actions.extend(self._recorder.flush())
            if self._actions or self._decision is not None:
                await self._relay.drained()  # the next observation shows what the person did
                if self._actions:
                    self._steps += 1
                    self.server.send(Progress(steps=self._steps, ready=False))
                    return self._actions.popleft()
                assert self._decision is not None
                return self._decision
            waits = [self._recorder.next_deadline()]
            if self._left_at is not None:
                if now - self._left_at >= self.reconnect_grace_s:
                    raise ParticipantLeftError(
                        f"the participant's page closed and stayed closed for {self.reconnect_grace_s:g} s "
                        "without Submit or Give up"
                    )
                waits.append(self._left_at + self.reconnect_grace_s)
            deadline = min((wait for wait in waits if wait is not None), default=None)
            self._changed.clear()
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(self._changed.wait(), None if deadline is None else max(deadline - now, 0))

    async def finish(self, end: EpisodeEnd) -> None:
        if self.server is not None:
            self.server.send(Ended(reason=end.stop_reason, steps=end.steps))
        await self._close()

    async def _close(self) -> None:
        if self._relay is not None:
            await self._relay.close()
        if self._screencast is not None:
            await self._screencast.stop()
        if self.server is not None:
            await self.server.stop()
