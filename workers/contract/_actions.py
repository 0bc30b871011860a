"""Actions an agent can take, as one tagged union so every step is validated data, and the answer to every
action in both modes (``ActionEnvelope``), so agents and logs read one shape."""

from __future__ import annotations

from typing import Annotated, Literal, TypeVar

from pydantic import BaseModel, ConfigDict, Field, JsonValue, ValidationError


class Done(BaseModel):
    """The agent believes the task is complete."""

    model_config = ConfigDict(frozen=True, extra="forbid")
    name: Literal["done"] = "done"


class Failed(BaseModel):
    """The agent gives up."""

    model_config = ConfigDict(frozen=True, extra="forbid")
    name: Literal["failed"] = "failed"
    reason: str = ""


class LoadProject(BaseModel):
    """Replace the whole project (privileged: only the oracle may use it)."""

    model_config = ConfigDict(frozen=True, extra="forbid")
    name: Literal["load_project"] = "load_project"
    sb3: bytes = Field(repr=False)


class InvalidReply(BaseModel):
    """A model reply that held no usable action: it costs the step, and the reason goes back to the model."""

    model_config = ConfigDict(frozen=True, extra="forbid")
    name: Literal["invalid_reply"] = "invalid_reply"
    reason: str
    message: str


class CompositeAction(BaseModel):
    """One call of the composite (semantic block-editing) API, e.g. ``add_block``.

    The page validates the api and its arguments and answers every mistake with an error
    envelope, so one place owns the rules and their error codes.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")
    name: Literal["composite"] = "composite"
    api: str
    args: dict[str, JsonValue] = Field(default_factory=dict)


class PrimitiveAction(BaseModel):
    """One low-level GUI action (click, drag_and_drop, type, ...) in page pixels or by element index.

    Arguments are checked when the action runs, so a malformed one costs the agent a step and
    comes back as an error envelope, exactly like a refused composite call.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")
    name: Literal["primitive"] = "primitive"
    api: str
    args: dict[str, JsonValue] = Field(default_factory=dict)


Action = Annotated[
    Done | Failed | LoadProject | InvalidReply | CompositeAction | PrimitiveAction, Field(discriminator="name")
]
"""Every action the environment understands; composite and primitive actions join this union."""

_ApiAction = TypeVar("_ApiAction", CompositeAction, PrimitiveAction)

FINAL_ACTIONS = frozenset({"done", "failed"})
"""Actions that end the episode."""


def composite_action(request: dict[str, JsonValue]) -> Done | Failed | InvalidReply | CompositeAction:
    """An agent's ``{"api": ..., "args": {...}}`` as a composite action; ``done``/``failed`` end the episode."""
    return _agent_action(request, CompositeAction)


def primitive_action(request: dict[str, JsonValue]) -> Done | Failed | InvalidReply | PrimitiveAction:
    """An agent's ``{"api": ..., "args": {...}}`` as a primitive action; ``done``/``failed`` end the episode."""
    return _agent_action(request, PrimitiveAction)


def _agent_action(request: dict[str, JsonValue], kind: type[_ApiAction]) -> Done | Failed | InvalidReply | _ApiAction:
    """The action, or (for arguments that are no action's, e.g. nested past any depth) an invalid reply
    that costs the agent its step: a model's garbage is its mistake, never an agent crash."""
    api, args = request.get("api"), request.get("args") or {}
    if api == "done":
        return Done()
    if api == "failed":
        reason = args.get("reason", "") if isinstance(args, dict) else ""
        return Failed(reason=str(reason))
    try:
        return kind(api=str(api), args=args if isinstance(args, dict) else {"_invalid": args})
    except ValidationError as exc:
        problem = exc.errors()[0]["msg"]
        return InvalidReply(reason="bad_args", message=f"the arguments of {str(api)[:100]!r} are not usable: {problem}")


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
