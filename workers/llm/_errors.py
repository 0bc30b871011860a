"""Why a model reply holds no usable action (``ModelCallError``, for calls that fail, is in the contract)."""

from __future__ import annotations

from typing import Literal

from workers.contract import ScratchWorldError

ParseFailure = Literal["no_json", "invalid_json", "missing_api", "bad_api", "bad_args"]
"""Why a reply could not be parsed."""


class ReplyParseError(ScratchWorldError):
    """A model reply holds no usable action; ``str(error)`` is written to be shown back to the model."""

    def __init__(self, reason: ParseFailure, message: str) -> None:
        super().__init__(message)
        self.reason: ParseFailure = reason
