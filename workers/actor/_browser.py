"""What a worker hands every kind whose jobs open editors: its browser, the pool of recycled editors, and the
evaluator that judges projects in them.

A verdict on the virtual evaluation clock does not depend on how fast the evaluation runs, while every step of
an episode waiting on its model counts in its latency. So while agents of this worker act, a virtual-clock
evaluation can run in a second browser in Linux's idle scheduling class (``evaluate_giving_way``), which gets
only the CPU time the agents' browser leaves over (measured with 32 episodes on 2 cores: their last steps had
waited seconds for the evaluations of the first).
"""

from __future__ import annotations

import asyncio

from playwright.async_api import Error as PlaywrightError

from workers.contract import EditorError, EvalResult, EvaluationSpec, ProjectLimits
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator

EVALUATIONS_AT_ONCE = 2
"""Evaluations the background browser runs at once (each is CPU-bound: more would only make each later and hold
more editors)."""


class WorkerBrowser:
    """One browser session with its editor pool and evaluator, shared by every job of a worker at once."""

    def __init__(self, session: BrowserSession, pool: EditorPool | None = None) -> None:
        """With a ``pool``, agent and evaluation pages are reused (it closes with the session)."""
        self.session = session
        self.pool = pool
        self.evaluator = Evaluator(session, pool)
        self.acting = 0
        """Agents of this browser's jobs in their loop (waiting on their models or acting): their runner counts them."""
        self._background: Evaluator | None = None
        self._background_opening = asyncio.Lock()
        self._background_turns = asyncio.Semaphore(EVALUATIONS_AT_ONCE)
        self._background_start: asyncio.Future[None] | None = None

    async def evaluate_giving_way(self, project: bytes, spec: EvaluationSpec, limits: ProjectLimits) -> EvalResult:
        """The verdict on ``project``: in the idle-class browser while agents act and the clock is virtual (the
        verdict is the same, the agents' steps are not slowed), else in this browser."""
        if not (self.acting and spec.clock == "virtual"):
            return await self.evaluator.evaluate(project, spec, limits)
        async with self._background_turns:
            background = await self._background_evaluator()
            evaluation = await background.evaluate(project, spec, limits)
            await background.session.keep_idle()
            return evaluation

    def start_background(self) -> asyncio.Future[None]:
        """Begin starting the low-priority browser, with its bare evaluation pages, ahead of the first evaluation (one
        that comes first waits for the browser's launch, not for its pages). A worker begins it as its first episodes
        start, while their first steps wait on the model: awaited before them, after the editors' openings, it held the
        start of 32 episodes on 2 cores back by 3-5 s; begun with the openings, it slowed them as much. Begun later,
        while agents act, the browser (and its driver, and its pages' files served from this process, at normal
        priority) held up their steps by seconds (measured with 16 episodes on 2 cores). Answers the start, to await
        when it must be over."""
        if self._background_start is None:
            self._background_start = asyncio.ensure_future(self._start_background())
        return self._background_start

    async def _start_background(self) -> None:
        try:
            background = await self._background_evaluator()
            if background.pool is not None:
                await background.pool.fill(EVALUATIONS_AT_ONCE, "bare")
                await background.session.keep_idle()
        except (EditorError, PlaywrightError):
            pass  # the first evaluation that needs the browser starts it again, or reports why it cannot

    async def _background_evaluator(self) -> Evaluator:
        """The evaluator of the low-priority browser, started (again, if it died) on first use."""
        async with self._background_opening:
            if self._background is None or not self._background.session.connected:
                await self._close_background()
                session = await BrowserSession(self.session.config.model_copy(update={"idle_priority": True})).start()
                self._background = Evaluator(session, EditorPool(session, spare=0))
            return self._background

    @property
    def background(self) -> Evaluator | None:
        """The evaluator that gives way to acting agents, once one evaluation has needed it."""
        return self._background

    @property
    def editors_held(self) -> int:
        """Editors of both browsers: waiting, lent or opening."""
        held = self.pool.held if self.pool is not None else 0
        background = self._background.pool if self._background is not None else None
        return held + (background.held if background is not None else 0)

    async def _close_background(self) -> None:
        background, self._background = self._background, None
        if background is not None:
            if background.pool is not None:
                await background.pool.close()
            await background.session.close()

    async def close(self) -> None:
        """Close the background browser (the session and pool belong to whoever made them), once a start of it
        under way has ended (cut short, a browser being launched could be left behind). A start that failed or
        was cancelled stops nothing: whatever of the browser it had opened is closed all the same."""
        if self._background_start is not None:
            await asyncio.wait([self._background_start])  # its outcome is not this close's to raise
        await self._close_background()
