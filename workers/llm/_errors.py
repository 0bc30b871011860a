"""The llm agent's errors, under the project's root ``ScratchWorldError``::

ScratchWorldError
├── ReplyParseError     a model reply holds no usable action (the message is feedback for the model)
└── ModelCallError      a model call failed for good (classified; never carries secrets)
"""

from __future__ import annotations

from typing import Literal

from workers._errors import ScratchWorldError

ParseFailure = Literal["no_json", "invalid_json", "missing_api", "bad_api", "bad_args"]
"""Why a reply could not be parsed."""

ModelErrorClass = Literal[
    "rate_limited",  # 429 from the provider
    "provider_error",  # 5xx, a malformed answer, or another server-side failure
    "timeout",  # the request outlived its timeout
    "connection",  # refused, reset or dropped connection
    "auth",  # 401/403: key missing, wrong or not allowed
    "bad_request",  # 400/422: the request itself is wrong
    "not_found",  # 404: unknown model or route
    "context_window",  # the prompt does not fit the model
    "content_policy",  # the provider refused the content
    "circuit_open",  # recent calls to this model all failed; failing fast during the cool-down
]
"""What went wrong with a model call, as reported in results."""


class ReplyParseError(ScratchWorldError):
    """A model reply holds no usable action; ``str(error)`` is written to be shown back to the model."""

    def __init__(self, reason: ParseFailure, message: str) -> None:
        super().__init__(message)
        self.reason: ParseFailure = reason


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
