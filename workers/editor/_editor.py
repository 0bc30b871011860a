"""One open editor page and the bridge calls Python makes into it.

Every call goes through the same constant JavaScript, ``scratchworld.call(name, args)``, with
JSON arguments; the page answers with an envelope that becomes a value or a ``BridgeError``.
"""

from __future__ import annotations

import asyncio
import base64
import contextlib
import time
from collections.abc import AsyncIterator, Awaitable, Callable
from contextlib import asynccontextmanager
from typing import Any

from playwright.async_api import BrowserContext, ConsoleMessage, Page
from playwright.async_api import Error as PlaywrightError
from playwright.async_api import TimeoutError as PlaywrightTimeoutError
from pydantic import BaseModel, ConfigDict, Field, JsonValue, ValidationError
from pydantic.alias_generators import to_camel

from workers._held_tasks import hold
from workers.contract import (
    BridgeError,
    EditorCrashedError,
    EditorError,
    EditorNotReadyError,
    EpisodeClock,
    EvaluationPage,
    EvaluationPerturbation,
    EvaluationSpec,
    ProjectLimits,
    RendererUnavailableError,
    check_project,
)

_CALL = "([name, args]) => window.scratchworld.call(name, args)"
_SETTLED = "() => !!(window.scratchworld && window.scratchworld.settled())"
EMPTY_START_QUERY = "start=empty"
"""The editor page's query for an editor opened ahead: its default project is an empty stage."""

CONSOLE_LINE_LIMIT = 400
"""Console lines kept per page; the editor itself is chatty at start-up."""

CLOSE_TIMEOUT_S = 15.0

RELEASED_KEYS = ("Shift", "Control", "Alt", "Meta")
"""Keys released before a page is reused (gestures press others only within one call)."""


class EditorStatus(BaseModel):
    """What the bridge reports about the page; ready means VM, workspace and project exist."""

    model_config = ConfigDict(alias_generator=to_camel, populate_by_name=True)

    page: EvaluationPage = "editor"
    """The editor, or the bare evaluation page (no workspace, no default project)."""
    vm: bool
    workspace: bool
    project_loads: int
    renderer: bool
    renderer_name: str | None
    stage_canvas: tuple[int, int] | None
    loading_state: str | None
    device_pixel_ratio: float = 1.0
    mouse_known: bool = False
    stepping: bool = False
    """The VM steps (a page waiting for use, parked or recycled, does not)."""
    audio: str | None = None
    """The VM's AudioContext's state: "running", or "suspended" while the page waits (or on the virtual clock)."""
    workspace_audio: list[str] = []
    """The states of the Blockly workspaces' AudioContexts (click sounds): "suspended" once the page has
    waited, parked or on the virtual clock, and from then on (``scratch-gui/audio.js``)."""
    other_audio: list[str] = []
    """The states of the page's other AudioContexts (the GUI's own, made on the first gesture): as the VM's."""

    def missing(self, kind: EvaluationPage = "editor") -> list[str]:
        """What a page of ``kind`` still lacks to be ready (the bare page needs its VM only)."""
        parts = {"VM": self.vm}
        if kind == "editor":
            parts |= {"rendered workspace": self.workspace, "default project": self.project_loads >= 1}
        return [name for name, present in parts.items() if not present]


class _Envelope(BaseModel):
    ok: bool
    value: JsonValue = None
    error: dict[str, str] | None = None


class StageRect(BaseModel):
    x: float
    y: float
    width: float
    height: float


class StageLayout(BaseModel):
    """The stage canvas's pixel size and where the stage sits on the page."""

    model_config = ConfigDict(alias_generator=to_camel, populate_by_name=True)

    canvas: tuple[int, int]
    stage_rect: StageRect


class _Loaded(BaseModel):
    targets: list[str]


class _Saved(BaseModel):
    sb3_base64: str = Field(alias="sb3Base64")


class _Recycled(BaseModel):
    differences: list[str]


class _Released(BaseModel):
    released: bool
    """True if a held palette was sent on to be drawn (the page is settled again once it is)."""


class EvaluationRun(BaseModel):
    """What a script returned (as JSON text) and how long it ran on the page's clock."""

    result_json: str = Field(alias="resultJson")
    duration_ms: float = Field(alias="durationMs")
    frames: list[tuple[float, float, int, int, float]] | None = None
    """With ``trace_frames``: per VM frame, its start on the page clock and on the real clock (ms), the
    block functions it called, whether it asked for a redraw (1/0) and the real ms it took."""

    notes: dict[str, JsonValue] = Field(default_factory=dict)
    """What the page's watches of the run reported (``earlyStop``: the test that failed first and how many were
    not run, under ``EvaluationSpec.stop_at_first_failure``)."""


Release = Callable[[list[Page]], Awaitable[None]]
"""Closes an editor's pages in a shared context and clears its origin (``SharedContext.release``)."""


class Editor:
    """A Scratch editor (or a bare evaluation page) in its own browser context, or at its own origin in a
    shared one (``release`` given); close it to free the context or the origin."""

    def __init__(
        self, context: BrowserContext, page: Page, kind: EvaluationPage = "editor", release: Release | None = None
    ) -> None:
        self.context = context
        self.page = page
        self._release = release
        self.shared = release is not None
        """In a context shared with other editors (closing it closes only this editor's pages)."""
        self._popups: list[Page] = []
        """Pages this editor's page (or one of them) opened: its own, to check on recycling and close with it."""
        self.kind: EvaluationPage = kind
        """The editor page, or the bare evaluation page (evaluations only: no blocks, no GUI)."""
        self.console: list[str] = []
        self.ready_s: float | None = None
        """Seconds from navigation to a ready editor, once ``open`` succeeded."""
        self.page_errors: list[str] = []
        self.uses = 0
        """Evaluations and episodes this editor has served (more than one only when an ``EditorPool`` reuses it)."""
        self.reusable = True
        """False once something happened that recycling cannot vouch for (a killed script)."""
        self._crashed = False
        page.on("console", self._on_console)
        page.on("pageerror", lambda exc: self.page_errors.append(str(exc)))
        page.on("crash", self._on_crash)
        page.on("popup", self._on_popup)

    def _on_popup(self, popup: Page) -> None:
        self._popups.append(popup)
        popup.on("popup", self._on_popup)

    def _on_console(self, message: ConsoleMessage) -> None:
        if len(self.console) < CONSOLE_LINE_LIMIT:
            self.console.append(f"{message.type}: {message.text}")

    def _on_crash(self, _page: Page) -> None:
        self._crashed = True

    async def call(self, name: str, args: dict[str, Any] | None = None) -> JsonValue:
        """Invoke a bridge function; raise ``BridgeError`` when the page reports a failure."""
        try:
            raw = await self.page.evaluate(_CALL, [name, args or {}])
        except PlaywrightError as exc:
            if self._crashed or self.page.is_closed():
                what = "crashed" if self._crashed else "went away"
                raise EditorCrashedError(f"the editor page {what} during {name}: {exc.message}") from exc
            raise EditorError(f"the bridge call {name} failed in the page: {exc.message}") from exc
        envelope = _Envelope.model_validate(raw)
        if not envelope.ok:
            error = envelope.error or {}
            raise BridgeError(error.get("kind", "bridge_error"), error.get("message", "no message"))
        return envelope.value

    async def open(self, url: str, timeout_s: float, *, draw_palette: bool = True) -> EditorStatus:
        """Navigate to the editor and wait (bounded) until it is ready; fail loudly otherwise.

        ``draw_palette=False``, for an editor opened ahead, whose every use loads a project first: the palette
        stays undrawn until the page's first project load, which draws that project's own
        (``scratch-gui/first-palette.js``), and the editor starts with an empty stage instead of the default
        project (``scratch-gui/empty-start.js``); they save drawing the default project's palette (0.3-0.45
        CPU-s here) and loading its sprite (about 0.1)."""
        started = time.monotonic()
        deadline = started + timeout_s
        if not draw_palette and self.kind == "editor":
            url = f"{url}?{EMPTY_START_QUERY}"
        try:
            await self.page.goto(url, wait_until="domcontentloaded", timeout=timeout_s * 1000)
            remaining = max(deadline - time.monotonic(), 0.1)
            await self.page.wait_for_function(_SETTLED, timeout=remaining * 1000, polling=50)
            if draw_palette:
                await self.draw_palette(max(deadline - time.monotonic(), 0.1))
        except PlaywrightError as exc:
            if self._crashed or self.page.is_closed():
                raise EditorCrashedError(f"the editor page went away while opening: {exc.message}") from exc
            raise EditorNotReadyError(await self._not_ready_reason(timeout_s, time.monotonic() - started, exc)) from exc
        status = await self.status()
        if not status.renderer:
            raise RendererUnavailableError(
                "the editor has no WebGL renderer (vm.renderer is null): touching, colour sensing and "
                "edge bounce would silently fail; Chromium needs a software GL (SwiftShader), so do not "
                "pass --disable-software-rasterizer"
            )
        self.ready_s = time.monotonic() - started
        await self.call("markClean")  # what recycling compares a used page with
        return status

    async def draw_palette(self, timeout_s: float = 10.0) -> None:
        """Draw the palette held since an opening without it (``draw_palette=False``: the empty stage's) while no
        project has loaded; nothing to do otherwise (a bare page has none). Returns once it is drawn."""
        if self.kind == "editor" and _Released.model_validate(await self.call("drawPalette")).released:
            await self.page.wait_for_function(_SETTLED, timeout=timeout_s * 1000, polling=50)

    async def _not_ready_reason(self, timeout_s: float, elapsed_s: float, exc: PlaywrightError) -> str:
        if isinstance(exc, PlaywrightTimeoutError):
            reason = f"the editor was not ready after {timeout_s:.0f} s"
        else:  # e.g. the navigation was aborted: a browser that is going away, before it says so
            reason = f"the editor page failed to load after {elapsed_s:.1f} s"
        try:
            status = await self.status()
            reason += f"; still missing: {', '.join(status.missing(self.kind)) or 'nothing'}"
        except (EditorError, BridgeError, ValidationError):
            reason += f" ({exc.message.splitlines()[0]})"
        if self.page_errors:
            reason += f"; page errors: {' | '.join(self.page_errors[:3])}"
        return reason

    async def status(self) -> EditorStatus:
        return EditorStatus.model_validate(await self.call("status"))

    async def set_stage_size(self, size: str) -> StageLayout:
        """Switch to the small or large stage; returns once the renderer's canvas has the new size."""
        return StageLayout.model_validate(await self.call("setStageSize", {"size": size}))

    async def move_mouse(self, x: float, y: float) -> None:
        """A real mouse event at page coordinates (x, y)."""
        try:
            await self.page.mouse.move(x, y)
        except PlaywrightError as exc:
            raise EditorCrashedError(f"could not move the mouse: {exc.message}") from exc

    async def load_project(self, sb3: bytes, limits: ProjectLimits | None = None) -> list[str]:
        """Load project bytes into the VM; return the names of its targets.

        The bytes are checked first (``ProjectFormatError``, ``ProjectTooLargeError``): the page
        never sees a project over ``limits`` (default: ``ProjectLimits()``).
        """
        check_project(sb3, limits)
        value = await self.call("loadProject", {"sb3Base64": base64.b64encode(sb3).decode("ascii")})
        return _Loaded.model_validate(value).targets

    async def save_project(self) -> bytes:
        """The current project as .sb3 bytes, as the editor would save it."""
        return base64.b64decode(_Saved.model_validate(await self.call("saveProject")).sb3_base64)

    async def run_evaluation(
        self,
        spec: EvaluationSpec,
        *,
        trace_frames: bool = False,
        observable_trace_chars: int | None = None,
        runner: dict[str, JsonValue] | None = None,
        observe_reads: bool = False,
    ) -> EvaluationRun:
        """Run an evaluation script on the loaded project, on the spec's clock (``trace_frames``: and
        record every VM frame, see ``EvaluationRun.frames``; ``observable_trace_chars``: and record what a
        user could observe, up to that many characters of JSON, see ``take_observable_trace``;
        ``observe_reads``: and what the script reads, see ``take_observed_reads``). ``runner``
        (``{"name", "args"}``) runs one of the page's own scripts instead of the spec's (``scratch-gui/explore/``),
        under the same conditions.

        The page enforces ``spec.timeout_s`` itself (on its clock, so in simulated seconds under
        the virtual clock); a script that blocks the page entirely is the caller's to kill (by
        closing the editor).
        """
        args = {
            "scriptName": spec.script_name,
            "scriptSource": spec.script_source,
            "helperName": spec.helper_name,
            "helperSource": spec.helper_source,
            "helperGlobal": spec.helper_global,
            "config": spec.config,
            "timeoutMs": spec.timeout_s * 1000,
            "clock": spec.clock,
            "render": spec.render,
            "perturbation": _perturbation_args(spec.perturbation),
            "frameTiming": spec.frame_lateness.bridge_args() if spec.frame_lateness else None,
            "traceFrames": trace_frames,
            "stopAtFirstFailure": spec.stop_at_first_failure,
        }
        if observable_trace_chars is not None:
            args["observableTrace"] = {"maxChars": observable_trace_chars}
        if runner is not None:
            args["runner"] = runner
        if observe_reads:
            args["observeReads"] = True
        self.uses += 1
        return EvaluationRun.model_validate(await self.call("evaluate", args))

    async def take_observable_trace(self) -> JsonValue:
        """The observable trace of the last ``run_evaluation`` that asked for one (``scratch-gui/trace/record.js``),
        also when its script failed; None when there is none. The page forgets it once taken."""
        return await self.call("takeObservableTrace")

    async def take_observed_reads(self) -> JsonValue:
        """What the script of the last ``run_evaluation`` with ``observe_reads`` read and started
        (``scratch-gui/trace/reads.js``); None when there is none. The page forgets it once taken."""
        return await self.call("takeObservedReads")

    async def recycle(self) -> list[str]:
        """Undo what the last evaluation or episode left in the page (``scratch-gui/recycle.js``,
        ``recycle-gui.js``).

        Returns what could not be undone or differs from the fresh page; only an editor with no
        differences may serve again, after ``resume``.
        """
        self.console.clear()  # the next use gets the whole console allowance
        self.page_errors.clear()
        if opened := [popup for popup in self._popups if not popup.is_closed()]:
            return [f"the page opened {len(opened)} more (a link or popup)"]
        try:  # what an agent's gesture may leave half done: pressed keys and buttons, an open menu
            for key in RELEASED_KEYS:
                await self.page.keyboard.up(key)
            await self.page.keyboard.press("Escape")
            for button in ("left", "right", "middle"):
                await self.page.mouse.up(button=button)
            await self.page.mouse.move(0, 0)  # so that the next profile's mouse move is a real move
        except PlaywrightError as exc:
            return [f"the page did not take the input reset: {exc.message}"]
        value = _Recycled.model_validate(await self.call("recycle"))
        return value.differences

    async def start_episode_clock(self, clock: EpisodeClock) -> None:
        """Put the page on the episode's clock: real, or virtual time that moves only in ``advance_clock``."""
        await self.call("episodeClock", {"mode": clock.mode})

    async def seed_random(self, seed: int) -> None:
        """Have the page's ``Math.random`` draw from ``seed`` until it is recycled: an episode's random
        sprites start where they would on a rerun (``workers.contract.evaluation_seed``)."""
        await self.call("seedRandom", {"seed": seed})

    async def advance_clock(self, ms: int, *, draw: bool = True) -> None:
        """Let ``ms`` of virtual time pass on a page whose episode runs on the virtual clock; ``draw=False``
        leaves the stage's picture as it was until an advance that draws (the VM's state moves on either way)."""
        await self.call("advanceClock", {"ms": ms, "draw": draw})

    async def redraw_panels(self) -> None:
        """Have the editor draw its sprite panels anew from the VM. It drops updates that come within
        500 ms (on the page clock) of the last one, so what a panel shows after a project load would
        depend on how fast the load went; redrawn after the virtual start, it shows the same thing."""
        await self.call("redrawPanels")

    async def collect_garbage(self) -> None:
        """A full collection of the page's JavaScript heap. A page that has just opened, or loaded a project and
        run its first second, holds the garbage of doing so until V8 gets round to it (tens of seconds later in
        a page that waits: 8 parked editors, 197 MB PSS each, held 171 MB 40 s later): collected at once, a
        waiting editor holds about 35 MB less (235 -> 200 MB PSS, 4 editors on 2 cores). It costs the page's
        renderer about 0.27 CPU-s. Nothing the page runs can tell."""
        try:
            devtools = await self.page.context.new_cdp_session(self.page)
            try:
                await devtools.send("HeapProfiler.collectGarbage")
            finally:
                await devtools.detach()
        except PlaywrightError as exc:
            raise EditorCrashedError(f"could not collect the page's garbage: {exc.message}") from exc

    async def park(self) -> None:
        """Stop the VM and suspend the audio of a fresh page that waits to be used (``resume`` starts
        both again), as a recycled page waits: a stepping VM costs about a third of a core, the
        editor's three running AudioContexts ~0.02 (``scratch-gui/audio.js``)."""
        await self.call("park")

    async def resume(self) -> None:
        """Start the VM and the audio of a parked or recycled page again (it waits for use without them)."""
        await self.call("resume")

    async def clock_status(self) -> dict[str, JsonValue]:
        """The page clock's mode and readings (real and virtual), for checks and diagnostics."""
        value = await self.call("clockStatus")
        if not isinstance(value, dict):
            raise EditorError(f"clockStatus returned {type(value).__name__}, not an object")
        return value

    async def close(self) -> None:
        """Close the context (or, in a shared one, the pages and then the origin's storage), even when the page
        is stuck in a busy loop; a cancelled close still completes."""
        if self.shared:
            release, self._release = self._release, None
            if release is None:  # closed already
                return
            await asyncio.shield(hold(release([self.page, *self._popups])))  # held on if this close is cancelled
            return
        # A browser that is gone or wedged is noticed by the session on its next use.
        with contextlib.suppress(PlaywrightError, TimeoutError):
            await asyncio.wait_for(self.context.close(), CLOSE_TIMEOUT_S)


@asynccontextmanager
async def opened(opening: Awaitable[Editor]) -> AsyncIterator[Editor]:
    """The editor ``opening`` yields, closed on exit whatever happens inside."""
    editor = await opening
    try:
        yield editor
    finally:
        await editor.close()


def _perturbation_args(perturbation: EvaluationPerturbation | None) -> dict[str, object] | None:
    """The bridge's view of a perturbation (the mouse is placed from Python, before the project loads)."""
    if perturbation is None:
        return None
    lateness = perturbation.lateness
    return {
        "randomSeed": perturbation.random_seed,
        "phaseMs": perturbation.phase_ms,
        "lateness": None if lateness is None else {"model": lateness.model, "ms": lateness.ms, "seed": lateness.seed},
    }
