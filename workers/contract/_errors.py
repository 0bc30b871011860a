"""Errors raised by the worker side; the root of the project's single exception hierarchy.

The whole tree is drawn in ``scratchworld_dist._errors``, which adds the driver's suite errors.
Playwright errors are translated here at the edge with ``raise ... from exc``.
"""

from __future__ import annotations

from typing import Literal

ModelErrorClass = Literal[
    "model_rate_limited",  # 429 from the provider
    "model_provider_error",  # 5xx, a malformed answer, or another server-side failure
    "model_timeout",  # the request outlived its timeout
    "model_connection",  # refused, reset or dropped connection
    "model_auth",  # 401/403: key missing, wrong or not allowed
    "model_bad_request",  # 400/422: the request itself is wrong
    "model_not_found",  # 404: unknown model or route
    "model_context_window",  # the prompt does not fit the model
    "model_content_policy",  # the provider refused the content
    "model_circuit_open",  # recent calls to this model all failed; failing fast during the cool-down
]
"""Why a model call failed for good; a job it ends has this as its error class."""


class ScratchWorldError(Exception):
    """Root of every error raised on purpose by scratchworld_dist and its workers."""


class AgentUnableError(ScratchWorldError):
    """An agent cannot go on and would fail the same way if the job ran again (a scripted plan the editor
    cannot act out): recorded as ``agent_unable``, an error the driver does not retry."""


class ParticipantLeftError(ScratchWorldError):
    """A person's page (the human agent's) closed before they submitted or gave up, and did not come back in
    time: recorded as ``participant_left``, an error a resume runs again."""


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


class ModelCallError(ScratchWorldError):
    """A model call failed after the retries its class allows; the message never holds the API key."""

    def __init__(
        self,
        error_class: ModelErrorClass,
        message: str,
        *,
        transient: bool,
        attempts: int,
        status_code: int | None = None,
    ) -> None:
        super().__init__(message)
        self.error_class: ModelErrorClass = error_class
        self.transient = transient
        self.attempts = attempts
        self.status_code = status_code


class AgentUnavailableError(ScratchWorldError):
    """An agent cannot be found, imported or built with its parameters, or lacks what it needs."""
