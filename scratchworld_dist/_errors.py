"""The project's exception hierarchy.

Every error the library raises on purpose is one of these; Playwright and OS errors are
translated at the edge with ``raise ... from exc`` so callers catch one family::

    ScratchWorldError
    ├── ConfigError                 a sweep config is unreadable or invalid (names the file and fields)
    ├── RunDirError                 a run directory holds another sweep or unreadable results
    │   └── NotARunDirError         a folder named as a run that is none (missing, or without manifest.json)
    ├── SuiteError                  a task suite or task file cannot be used (names the file)
    │   └── TaskNotFoundError       a task id that the suite does not have
    ├── ProjectFormatError          bytes that are not a Scratch 3 project (.sb3)
    │   └── ProjectTooLargeError    a project over the size limits (checked before a browser sees it)
    ├── EditorError                 the Scratch editor cannot be brought up or kept alive
    │   ├── ChromiumNotFoundError   no Chromium executable where we were told to look
    │   ├── EditorBundleMissingError  the npm editor bundle is not installed
    │   ├── EditorNotReadyError     the page never became ready within its bounded wait
    │   ├── RendererUnavailableError  no WebGL renderer: sensing would silently fail
    │   └── EditorCrashedError      the page or browser died while in use
    ├── BridgeError                 the page refused a bridge call (carries the page's kind)
    ├── OCRError                    an OCR backend cannot run (missing package or model files)
    ├── ReplyParseError             a model reply holds no usable action (the message is shown to the model)
    ├── ModelCallError              a model call failed for good (classified; never carries the API key)
    └── OracleDivergenceError       the primitive oracle's page stopped matching its plan (workers.agents)

The root and the editor errors live in ``workers.contract`` (the worker side imports nothing
from the driver side); the suite errors are the driver's own.

Evaluation never raises for a bad project or a bad script: those become an ``EvalResult``
with an error (a failed sample is a row, not an exception).
"""

from __future__ import annotations

from pathlib import Path

from pydantic import ValidationError

from workers.contract import (
    BridgeError,
    ChromiumNotFoundError,
    EditorBundleMissingError,
    EditorCrashedError,
    EditorError,
    EditorNotReadyError,
    OCRError,
    ProjectFormatError,
    ProjectTooLargeError,
    RendererUnavailableError,
    ScratchWorldError,
)

__all__ = [
    "BridgeError",
    "ChromiumNotFoundError",
    "ConfigError",
    "EditorBundleMissingError",
    "EditorCrashedError",
    "EditorError",
    "EditorNotReadyError",
    "NotARunDirError",
    "OCRError",
    "ProjectFormatError",
    "ProjectTooLargeError",
    "RendererUnavailableError",
    "RunDirError",
    "ScratchWorldError",
    "SuiteError",
    "TaskNotFoundError",
    "validation_summary",
]


class SuiteError(ScratchWorldError):
    """A suite or one of its task files is unusable; the message names the file."""

    def __init__(self, message: str, path: Path | None = None) -> None:
        super().__init__(f"{path}: {message}" if path is not None else message)
        self.path = path


class TaskNotFoundError(SuiteError):
    """A requested task id is not part of the suite."""


class ConfigError(ScratchWorldError):
    """A sweep config cannot be read or fails validation; the message lists every bad field."""

    def __init__(self, message: str, path: Path | None = None) -> None:
        super().__init__(f"{path}: {message}" if path is not None else message)


class RunDirError(ScratchWorldError):
    """A run directory cannot be used as asked (another sweep, another suite, unreadable shards)."""


class NotARunDirError(RunDirError):
    """A folder named as a run directory that is not one: every command and the API say it in these words."""

    def __init__(self, path: Path | str, why: str, hint: str = "") -> None:
        super().__init__(f"{path}: not a scratchworld run directory ({why}){hint}")
        self.path = Path(path)


def validation_summary(exc: ValidationError, limit: int = 3) -> str:
    """Pydantic's complaints on one line (``field: problem; ...``), without the input it echoes."""
    problems = [f"{'.'.join(map(str, e['loc'])) or 'value'}: {e['msg']}" for e in exc.errors()[:limit]]
    more = exc.error_count() - len(problems)
    return "; ".join(problems) + (f" (and {more} more)" if more > 0 else "")
