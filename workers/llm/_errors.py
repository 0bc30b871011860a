"""The llm agent's errors, under the project's root ``ScratchWorldError``::

ScratchWorldError
├── ReplyParseError     a model reply holds no usable action (the message is feedback for the model)
└── ModelCallError      a model call failed for good (classified; never carries secrets)
"""

from __future__ import annotations

from typing import Literal

from workers.contract import ModelErrorClass, ScratchWorldError

ParseFailure = Literal["no_json", "invalid_json", "missing_api", "bad_api", "bad_args"]
"""Why a reply could not be parsed."""


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
