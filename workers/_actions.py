"""Actions an agent can take, as one tagged union so every step is validated data."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue


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


class CompositeAction(BaseModel):
    """One call of the composite (semantic block-editing) API, e.g. ``add_block``.

    The page validates the api and its arguments and answers every mistake with an error
    envelope, so one place owns the rules and their error codes.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")
    name: Literal["composite"] = "composite"
    api: str
    args: dict[str, JsonValue] = Field(default_factory=dict)


Action = Annotated[Done | Failed | LoadProject | CompositeAction, Field(discriminator="name")]
"""Every action the environment understands; composite and primitive actions join this union."""

FINAL_ACTIONS = frozenset({"done", "failed"})
"""Actions that end the episode."""


def composite_action(request: dict[str, JsonValue]) -> Done | Failed | CompositeAction:
    """An agent's ``{"api": ..., "args": {...}}`` as an action; ``done`` and ``failed`` end the episode."""
    api, args = request.get("api"), request.get("args") or {}
    if api == "done":
        return Done()
    if api == "failed":
        reason = args.get("reason", "") if isinstance(args, dict) else ""
        return Failed(reason=str(reason))
    return CompositeAction(api=str(api), args=args if isinstance(args, dict) else {"_invalid": args})
