"""Errors raised by the worker side; the root of the project's single exception hierarchy.

The whole tree is drawn in ``scratchworld_dist._errors``, which adds the driver's suite errors.
Playwright errors are translated here at the edge with ``raise ... from exc``.
"""

from __future__ import annotations


class ScratchWorldError(Exception):
    """Root of every error raised on purpose by scratchworld_dist and its workers."""


class ProjectFormatError(ScratchWorldError):
    """Bytes that cannot be a Scratch 3 project: not a zip, no project.json, bad JSON."""


class ProjectTooLargeError(ProjectFormatError):
    """A project over the size limits (the file, an entry inflated, the whole archive inflated)."""


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


class OCRError(ScratchWorldError):
    """An OCR backend cannot run: a missing package or model file, or the engine failed."""
