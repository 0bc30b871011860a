"""Execution-based evaluation: a project, a script, a verdict.

Each evaluation loads the project into a clean VM (a fresh editor page, never the page an agent
edited) and runs the task's script there with a hard timeout. Whatever goes wrong with the
project or the script (corrupt .sb3, a script that throws, hangs or returns garbage) comes back
as an ``EvalResult`` with a classified error; only a broken browser session raises.
"""

from __future__ import annotations

import asyncio
import json
import time

from pydantic import BaseModel, ConfigDict, Field, JsonValue

from workers._browser import BrowserSession
from workers._editor import Editor
from workers._errors import BridgeError, EditorError, ProjectFormatError
from workers._eval_result import EvalErrorKind, EvalResult, EvalTimings
from workers._report import ReportError, parse_report
from workers._sb3_reader import read_project_json

KILL_GRACE_S = 5.0
"""Extra time past the in-page timeout before the page itself is killed (a synchronous hang)."""

_BRIDGE_KINDS: dict[str, EvalErrorKind] = {
    "project_invalid": "project_invalid",
    "script_invalid": "script_invalid",
    "script_error": "script_error",
    "script_timeout": "script_timeout",
    "result_invalid": "result_invalid",
}


class EvaluationSpec(BaseModel):
    """Everything besides the project that an evaluation needs, as data that can cross processes."""

    model_config = ConfigDict(frozen=True)

    script_name: str
    """File name of the evaluation script, used in messages and stack traces."""

    script_source: str
    """CommonJS module source whose ``module.exports`` is ``async (vm, config, cleanup) => result``."""

    helper_name: str | None = None
    """File name of the suite's helper module, if any."""

    helper_source: str | None = None
    """Helper module source, installed as a global before the script loads."""

    helper_global: str = "EvaluationUtils"
    """Global name the helper's exports are published under (upstream: ``EvaluationUtils``)."""

    timeout_s: float = Field(gt=0)
    """Hard limit for the script; past it the result is a ``script_timeout``."""

    config: dict[str, JsonValue] = Field(default_factory=dict)
    """Second argument handed to the script (upstream always passes ``{}``)."""


class Evaluator:
    """Runs evaluations in fresh editors of one browser session; safe to use concurrently."""

    def __init__(self, session: BrowserSession) -> None:
        self.session = session

    async def evaluate(self, project: bytes, spec: EvaluationSpec) -> EvalResult:
        started = time.perf_counter()
        timings = EvalTimings()
        try:
            read_project_json(project)
        except ProjectFormatError as exc:
            timings.total_s = time.perf_counter() - started
            return EvalResult.failure("project_invalid", str(exc), timings=timings)
        try:
            async with self.session.editor() as editor:
                timings.editor_ready_s = editor.ready_s
                result = await self._evaluate_in(editor, project, spec, timings)
        except EditorError as exc:
            result = EvalResult.failure("editor_failure", f"{type(exc).__name__}: {exc}", timings=timings)
        result.timings.total_s = time.perf_counter() - started
        return result

    async def _evaluate_in(
        self, editor: Editor, project: bytes, spec: EvaluationSpec, timings: EvalTimings
    ) -> EvalResult:
        phase_start = time.perf_counter()
        try:
            await editor.load_project(project)
        except BridgeError as exc:
            return EvalResult.failure(_kind(exc), exc.detail, timings=timings)
        timings.project_load_s = time.perf_counter() - phase_start

        console_start = len(editor.console)
        phase_start = time.perf_counter()
        args = {
            "scriptName": spec.script_name,
            "scriptSource": spec.script_source,
            "helperName": spec.helper_name,
            "helperSource": spec.helper_source,
            "helperGlobal": spec.helper_global,
            "config": spec.config,
            "timeoutMs": spec.timeout_s * 1000,
        }
        try:
            value = await asyncio.wait_for(editor.call("evaluate", args), spec.timeout_s + KILL_GRACE_S)
        except TimeoutError:
            # The page is stuck in synchronous code; leaving the ``editor()`` block kills it.
            timings.script_s = time.perf_counter() - phase_start
            return EvalResult.failure(
                "script_timeout",
                f"{spec.script_name} blocked the page for over {spec.timeout_s + KILL_GRACE_S:.0f} s and was killed",
                console=editor.console[console_start:],
                timings=timings,
            )
        except BridgeError as exc:
            timings.script_s = time.perf_counter() - phase_start
            return EvalResult.failure(_kind(exc), exc.detail, console=editor.console[console_start:], timings=timings)
        timings.script_s = time.perf_counter() - phase_start
        console = editor.console[console_start:]

        assert isinstance(value, dict)
        try:
            report = parse_report(json.loads(str(value["resultJson"])))
        except ReportError as exc:
            return EvalResult.failure("result_invalid", f"{spec.script_name}: {exc}", console=console, timings=timings)
        return EvalResult(
            success=report.passed == report.total,
            passed=report.passed,
            total=report.total,
            psr=report.passed / report.total,
            tests=report.tests,
            warnings=report.warnings,
            console=console,
            timings=timings,
        )


def _kind(exc: BridgeError) -> EvalErrorKind:
    kind = _BRIDGE_KINDS.get(exc.kind)
    if kind is None:
        raise EditorError(f"the bridge failed unexpectedly: {exc}") from exc
    return kind
