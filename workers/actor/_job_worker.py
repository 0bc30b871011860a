"""The Ray actor behind every worker: one browser, several concurrent jobs of any kind, one page each.

Whatever happens inside a job comes back as a ``JobResult`` (an error outcome at
worst); only the death of the process itself is left to Ray and the driver. The browser is
started on first use and started again if it dies, so a restarted actor heals itself. The jobs in
a browser that dies end within seconds as editor failures, even those waiting on their model. An
episode whose editor failed closes its browser only if that browser stopped answering: a page
that crashed takes nobody else with it, and a late failure never closes a browser that was
started after it.

A job is run by its kind (``workers.kinds``, found by its spec class): episodes and regrades,
drag jobs, perception jobs, or a plugin's. A worker refuses jobs planned for another harness (the
driver's fingerprint of the job's kind differs from the code this process runs), so no node
produces verdicts under ids that name other code. It declines
(``Refusal``, not an attempt) to start a job while its node has less memory available than the
sweep's reserve: the driver sends it elsewhere or later, and Chromium is not pushed into the OOM
killer. Each result carries the worker's load: its editors, their memory and the node's.
"""

from __future__ import annotations

import asyncio
import contextlib
import os
import socket
import time
import traceback
from collections.abc import Awaitable

import ray
from playwright.async_api import Error as PlaywrightError
from pydantic import BaseModel

from workers.actor._browser import WorkerBrowser
from workers.contract import (
    MIB,
    EditorError,
    JobResult,
    Refusal,
    SyntheticEpisodes,
    WorkerInfo,
    WorkerJob,
    WorkerLoad,
)
from workers.editor import BrowserConfig, BrowserSession, EditorPool
from workers.kinds import WorkerKind, kind_fingerprint, kind_of, worker_kinds
from workers.llm import close_litellm_clients
from workers.llm import load_litellm as import_litellm
from workers.node import BrowserUsage, browser_usage, harness_fingerprint, node_memory
from workers.tracing import (
    TracingConfigError,
    configure_tracing,
    flush_spans,
    mark_error,
    parent_context,
    set_attributes,
    span,
)

OPENS_AT_ONCE = 1
"""Editors a worker's browser opens at once. A node runs one worker browser per core, and an opening keeps
more than one core busy (renderer, GPU and browser processes): two browsers filling 16 parked editors each
on 2 cores took 39 s and 70 CPU-s one at a time each, 48 s and 88 CPU-s two at a time."""

MEMORY_POLL_S = 0.5
"""How often a worker short of memory looks again."""

USAGE_MAX_AGE_S = 30.0
"""How old the browsers' memory (and the editors counted with it) a load may report. Reading every browser
process's PSS walks their page tables in the kernel: 0.16 s of CPU with 12 editors open, about 0.5 s with 32,
and each reading holds up the renderer it walks. Read every 5 s, that was a tenth of a core at 32 episodes on
2 cores, on top of their steps; after every job of a sweep of short jobs (grader audit variants: about 0.7 s
each) it was a twentieth of its workers' time. The node's available memory, which admission decides on, is
always read anew."""


class JobWorker:
    """Runs episodes for the driver; construct through ``ray.remote`` (see ``WorkerPool``)."""

    def __init__(
        self, worker_index: int, synthetic: SyntheticEpisodes | None = None, memory_reserve_bytes: int = 0
    ) -> None:
        self.synthetic = synthetic
        self.memory_reserve_bytes = memory_reserve_bytes
        if synthetic is not None:
            time.sleep(synthetic.startup_s)
        self.info_ = WorkerInfo(
            node_id=ray.get_runtime_context().get_node_id() if ray.is_initialized() else "local",
            hostname=socket.gethostname(),
            pid=os.getpid(),
            worker_index=worker_index,
        )
        self.full_harness = harness_fingerprint()
        """The harness this process runs (its code, editor and browser): a job planned for another
        fingerprint of its kind is refused."""
        self._kinds: dict[str, WorkerKind] | None = None
        self._kind_harness: dict[str, str] = {}
        self.kind_state: dict[str, object] = {}
        self._session: BrowserSession | None = None
        self._browser: WorkerBrowser | None = None
        self._starting = asyncio.Lock()
        self._usage: tuple[float, BrowserUsage, int] | None = None
        """The browsers' usage last read, when (``time.monotonic``), and the editors they held then."""
        with contextlib.suppress(TracingConfigError):  # the driver said it already; spans are not worth a worker
            configure_tracing()
        self._flushes_answer = True
        """Whether the span exporter took the last flush in time (if not, flushes no longer hold up a job)."""
        self._flushing: asyncio.Future[bool] | None = None

    async def info(self) -> WorkerInfo:
        return self.info_

    async def load(self) -> WorkerLoad:
        """This worker's editors and their memory, the node's available memory, and whether it takes jobs."""
        (usage, editors), memory = await asyncio.to_thread(lambda: (self._browser_usage(), node_memory()))
        return WorkerLoad(
            editors=editors,
            browser_pss_bytes=usage.pss_bytes,
            node_available_bytes=memory.available_bytes,
            admits=memory.available_bytes >= self.memory_reserve_bytes,
        )

    def _browser_usage(self) -> tuple[BrowserUsage, int]:
        """The browsers' usage and the editors they held, read together again once ``USAGE_MAX_AGE_S`` old (so
        that memory per editor is one moment's)."""
        now = time.monotonic()
        if self._usage is None or now - self._usage[0] >= USAGE_MAX_AGE_S:
            editors = self._browser.editors_held if self._browser is not None else 0
            self._usage = (now, browser_usage(), editors)
        return self._usage[1], self._usage[2]

    async def wait_admitting(self, within_s: float) -> WorkerLoad:
        """The load as soon as the node has its memory reserve available again, or after ``within_s``."""
        deadline = time.monotonic() + within_s
        load = await self.load()
        while not load.admits and time.monotonic() < deadline:
            await asyncio.sleep(MEMORY_POLL_S)  # the kernel has no event for "memory is free again"
            load = await self.load()
        return load

    async def warm(self, editors: int, calls_models: bool = False) -> WorkerInfo:
        """Start the browser and open ``editors`` editors ahead of the first jobs (they wait parked); with
        ``calls_models``, import LiteLLM meanwhile, and begin starting the browser that judges while agents
        act (``WorkerBrowser.start_background``: it goes on as the first episodes wait on their models). Answers
        where this worker is: the driver starts its jobs only once no other worker of its node still opens
        editors, so it must know the node when this returns.

        Opened while this worker's episodes run, each editor would slow their steps for seconds; and the
        LiteLLM import (3-9 s of one core, holding the interpreter) at the first job held up every episode
        of the worker as it started: measured with 16 episodes on 2 cores, the first steps waited 2-3 s.
        A worker with synthetic episodes configured opens none ahead. Never raises for a browser or editor
        that fails: the first job then meets the failure and reports it.
        """
        if self.synthetic is not None:
            index, taken = self.info_.worker_index, self.synthetic.warm_s
            if index < len(taken):
                await asyncio.sleep(taken[index])  # stands in for the openings
            return self.info_
        importing = asyncio.ensure_future(self.load_litellm()) if calls_models else None
        if editors > 0:
            try:
                browser = await self.browser()
                if browser.pool is not None:
                    await browser.pool.fill(editors)
                if calls_models and editors > 1:  # evaluations give way only to other agents of this worker
                    browser.start_background()
            except (EditorError, PlaywrightError):
                pass  # the first episode opens its own editor, or reports why it cannot
        if importing is not None:
            await importing
        return self.info_

    async def run(
        self,
        spec: WorkerJob,
        task: BaseModel,
    ) -> JobResult | Refusal:
        # The node's free memory alone decides (one read of /proc/meminfo); the browsers' PSS, which
        # means reading every process's smaps, only when the driver is told why the job was declined.
        if self.memory_reserve_bytes and node_memory().available_bytes < self.memory_reserve_bytes:
            load = await self.load()
            reason = (
                f"{self.info_.hostname} has {load.node_available_bytes / MIB:.0f} MB available, "
                f"under the {self.memory_reserve_bytes / MIB:.0f} MB reserve"
            )
            return Refusal(reason=reason, load=load)
        started, clock = time.time(), time.perf_counter()
        attributes = {
            "job_id": spec.job_id,
            "task": spec.task_id,
            "attempt": spec.attempt,
            "model": getattr(getattr(spec, "model", None), "name", None),
            "mode": getattr(spec, "mode", None),
        }
        parent = parent_context(getattr(spec, "trace_parent", None))  # a plugin's spec need not extend JobHeader
        with span("episode", parent, **attributes) as opened:
            try:
                result = await asyncio.wait_for(self._run(spec, task), timeout=spec.timeout_s)
            except TimeoutError:
                result = JobResult.errored(spec, "episode_timeout", f"episode exceeded {spec.timeout_s:g} s")
            except (EditorError, PlaywrightError) as exc:  # the browser could not be started
                result = JobResult.errored(spec, "editor_failure", f"{type(exc).__name__}: {exc}")
            except Exception as exc:  # the worker must answer, whatever broke: the driver records it
                detail = "".join(traceback.format_exception_only(exc)).strip()
                result = JobResult.errored(spec, "internal_error", detail)
            traced = opened.is_recording()  # an ended span no longer records
            if traced:
                set_attributes(
                    opened, outcome=result.outcome, error_class=result.error_class, steps=len(result.steps),
                    input_tokens=result.input_tokens, output_tokens=result.output_tokens,
                )  # fmt: skip
                if result.outcome == "error":
                    mark_error(opened, result.error_class or "error")
        if traced:
            await self._flush_spans()
        update: dict[str, object] = {"worker": self.info_, "load": await self.load()}
        if not result.started_at:  # an episode cut short never stamped itself
            timings = result.timings.model_copy(update={"total_s": time.perf_counter() - clock})
            update.update(started_at=started, finished_at=time.time(), timings=timings)
        return result.model_copy(update=update)

    async def _run(self, spec: WorkerJob, task: BaseModel) -> JobResult:
        if self._kinds is None:
            self._kinds = worker_kinds()
        kind = kind_of(spec, self._kinds)
        if kind is None:
            known = ", ".join(sorted(self._kinds))
            message = f"no job kind runs {type(spec).__name__} on this worker (registered kinds: {known})"
            return JobResult.errored(spec, "internal_error", message)
        harness = self.kind_harness(kind.name)
        if spec.harness is not None and spec.harness != harness:
            message = (
                f"{self.info_.hostname} (node {self.info_.node_id[:12]}) runs harness {harness}, "
                f"the job was planned for {spec.harness}: update this node's checkout"
            )
            return JobResult.errored(spec, "harness_mismatch", message)
        return await kind.run(self, spec, task)

    async def _flush_spans(self) -> None:
        """Export the job's spans before its result leaves: the driver may kill this actor next, without exit
        handlers. A collector that does not take them within 2 s costs that once; from then on they leave in the
        background (and as the batch processor's schedule sends them)."""
        if self._flushing is not None and not self._flushing.done():
            return  # one flush at a time: the one under way takes these spans too, or the schedule does
        self._flushing = asyncio.ensure_future(asyncio.to_thread(flush_spans))
        if self._flushes_answer:
            self._flushes_answer = await asyncio.shield(self._flushing)

    def kind_harness(self, kind: str) -> str:
        """The digest ``kind``'s jobs must be planned under here: this process's harness minus other kinds' code."""
        if kind not in self._kind_harness:
            self._kind_harness[kind] = kind_fingerprint(self.full_harness, kind, self._kinds).digest
        return self._kind_harness[kind]

    async def load_litellm(self) -> None:
        """LiteLLM imported once per process, before a job's first model call would wait for it."""
        await import_litellm()

    async def in_browser(self, spec: WorkerJob, session: BrowserSession, work: Awaitable[JobResult]) -> JobResult:
        """``work``'s result, cut short if ``session``'s browser dies; after an editor failure the browser is
        closed if it no longer answers."""
        try:
            result = await session.while_connected(work)
        except (EditorError, PlaywrightError) as exc:
            result = JobResult.errored(spec, "editor_failure", f"{type(exc).__name__}: {exc}")
        if result.error_class == "editor_failure":
            await self._drop_if_broken(session)
        return result

    async def browser(self) -> WorkerBrowser:
        """This worker's browser, editor pool and evaluator, started again if it died."""
        async with self._starting:
            if self._browser is None or not self._browser.session.connected:
                await self._drop_browser()
                self._session = await BrowserSession(BrowserConfig(concurrent_opens=OPENS_AT_ONCE)).start()
                # Agent and evaluation pages are recycled across this worker's jobs (verified as good as fresh).
                self._browser = WorkerBrowser(self._session, EditorPool(self._session, spare=0))
            return self._browser

    async def _drop_if_broken(self, session: BrowserSession) -> None:
        """Close the browser an episode failed in if it no longer answers; never another one."""
        if await session.responsive():
            return  # only the episode's own page broke: its siblings carry on
        if session is self._session:
            if self._browser is not None:
                await self._browser.close()
            self._session = self._browser = None
        await session.close()

    async def _drop_browser(self) -> None:
        session, browser, self._session, self._browser = self._session, self._browser, None, None
        if browser is not None:
            await browser.close()
        if session is not None:
            await session.close()

    async def close(self) -> None:
        await self._drop_browser()
        await close_litellm_clients()  # LiteLLM's HTTP sessions belong to this actor's event loop
