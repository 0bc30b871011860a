"""The project's exception hierarchy.

Every error the library raises on purpose is one of these; Playwright and OS errors are
translated at the edge with ``raise ... from exc`` so callers catch one family::

    ScratchWorldError
    ├── SuiteError                  a task suite or task file cannot be used (names the file)
    │   └── TaskNotFoundError       a task id that the suite does not have
    ├── ProjectFormatError          bytes that are not a Scratch 3 project (.sb3)
    ├── EditorError                 the Scratch editor cannot be brought up or kept alive
    │   ├── ChromiumNotFoundError   no Chromium executable where we were told to look
    │   ├── EditorBundleMissingError  the npm editor bundle is not installed
    │   ├── EditorNotReadyError     the page never became ready within its bounded wait
    │   ├── RendererUnavailableError  no WebGL renderer: sensing would silently fail
    │   └── EditorCrashedError      the page or browser died while in use
    └── BridgeError                 the page refused a bridge call (carries the page's kind)

Evaluation never raises for a bad project or a bad script: those become an ``EvalResult``
with an error (a failed sample is a row, not an exception).
"""

from __future__ import annotations

from pathlib import Path


class ScratchWorldError(Exception):
    """Root of every error raised on purpose by scratchworld_dist and its workers."""


class SuiteError(ScratchWorldError):
    """A suite or one of its task files is unusable; the message names the file."""

    def __init__(self, message: str, path: Path | None = None) -> None:
        super().__init__(f"{path}: {message}" if path is not None else message)
        self.path = path


class TaskNotFoundError(SuiteError):
    """A requested task id is not part of the suite."""


class ProjectFormatError(ScratchWorldError):
    """Bytes that cannot be a Scratch 3 project: not a zip, no project.json, bad JSON."""


class EditorError(ScratchWorldError):
    """The editor could not be started, made ready, or kept alive."""


class ChromiumNotFoundError(EditorError):
    """The Chromium executable is missing."""


class EditorBundleMissingError(EditorError):
    """The prebuilt Scratch GUI bundle from npm is not installed."""


class EditorNotReadyError(EditorError):
    """The editor page did not become ready within its bounded wait."""


class RendererUnavailableError(EditorError):
    """The VM has no WebGL renderer, so touching and colour sensing would silently fail."""


class EditorCrashedError(EditorError):
    """The page, its context or the browser went away while in use."""


class BridgeError(ScratchWorldError):
    """The in-page bridge answered a call with an error envelope."""

    def __init__(self, kind: str, message: str) -> None:
        super().__init__(f"{kind}: {message}")
        self.kind = kind
        self.detail = message
