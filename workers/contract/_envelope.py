"""The answer to every agent action, in both modes, so agents and logs read one shape."""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, JsonValue


class ActionFailure(BaseModel):
    """Why an action was refused; ``code`` is stable (INVALID_ARG, NOT_FOUND, STALE_INDEX, ...)."""

    model_config = ConfigDict(frozen=True)

    code: str
    message: str
    details: JsonValue = None


class ActionEnvelope(BaseModel):
    """The environment's answer to one action: data on success, a failure otherwise."""

    model_config = ConfigDict(frozen=True, populate_by_name=True)

    success: bool
    data: JsonValue = None
    error: ActionFailure | None = None
    duration_ms: float = Field(default=0.0, alias="durationMs")

    @classmethod
    def failure(cls, code: str, message: str, duration_ms: float = 0.0, details: JsonValue = None) -> ActionEnvelope:
        return cls(
            success=False, error=ActionFailure(code=code, message=message, details=details), duration_ms=duration_ms
        )
