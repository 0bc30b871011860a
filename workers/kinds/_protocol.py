"""What a job kind is on the worker side, and what it may use of the worker that runs it.

The actor knows no kind: it finds a job's kind by the job's spec class, checks the job was planned
for that kind's harness, and hands it over. A kind keeps its runner out of this module's imports
(``run`` imports it when a job comes), so listing the kinds loads neither Playwright nor LiteLLM.
"""

from __future__ import annotations

from collections.abc import Awaitable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

from pydantic import BaseModel

from workers.contract import JobResult, SyntheticEpisodes, WorkerInfo, WorkerJob

if TYPE_CHECKING:
    from workers.actor._browser import WorkerBrowser
    from workers.editor import BrowserSession


class WorkerHost(Protocol):
    """The worker a kind's runner runs in (``JobWorker``): its browser, pools, settings and identity."""

    info_: WorkerInfo
    """Who this worker is (messages name its host and node)."""

    synthetic: SyntheticEpisodes | None
    """The sweep's synthetic episodes, if any (benchmarks of the scheduler, no browser)."""

    kind_state: dict[str, object]
    """What a kind keeps across its jobs on this worker, by kind name (the drag kind: its DragRunner)."""

    async def browser(self) -> WorkerBrowser:
        """This worker's browser, its pool of recycled editors and its evaluator, started (again, if it died) on
        first use: every kind's jobs that open editors share them."""
        ...

    async def in_browser(self, spec: WorkerJob, session: BrowserSession, work: Awaitable[JobResult]) -> JobResult:
        """``work``'s result, cut short as an editor failure if ``session``'s browser dies."""
        ...

    async def load_litellm(self) -> None:
        """Import LiteLLM off the event loop, once per process, before a job's first model call."""
        ...


@dataclass(frozen=True)
class AgentGroup:
    """Where a kind's agents register and what each must have: the agent registry (``workers.agent_api``) finds
    and checks a kind's agents by it, so a kind that brings agents edits no table of that registry."""

    group: str
    """The entry-point group its agents are registered in (``scratchworld.drag_agents``)."""

    methods: tuple[str, ...]
    """The methods an agent of the kind must have (``answer``)."""

    base: str
    """The class messages point an agent's author to (``workers.agent_api.DragAgentBase``)."""


class WorkerKind(Protocol):
    """One benchmark as a worker runs it; registered under the ``scratchworld.worker_kinds`` entry points."""

    @property
    def name(self) -> str:
        """The kind's name, as a sweep config's ``benchmark:`` names it (``tasks``, ``drag``, ``perception``)."""
        ...

    @property
    def specs(self) -> tuple[type[BaseModel], ...]:
        """The job spec classes this kind runs; each belongs to one kind only."""
        ...

    @property
    def payloads(self) -> tuple[type[BaseModel], ...]:
        """What its jobs are sent with (the task, drag task or perception item)."""
        ...

    @property
    def code(self) -> tuple[str, ...]:
        """Paths under ``workers/`` (folders or files) that only this kind's jobs import.

        They are left out of the other kinds' harness fingerprints (see ``workers.kinds._fingerprint``).
        """
        ...

    @property
    def needs_browser(self) -> bool:
        """Whether its jobs open an editor (a perception job only asks a model about a stored screenshot)."""
        ...

    @property
    def agents(self) -> AgentGroup | None:
        """Where its agents register and what they must have; None (or no such attribute): its jobs run no agent."""
        ...

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        """One attempt of one job, whose harness the host has checked; an error outcome at worst."""
        ...
