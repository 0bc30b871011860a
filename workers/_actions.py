"""Actions an agent can take, as one tagged union so every step is validated data."""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field


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


Action = Annotated[Done | Failed | LoadProject, Field(discriminator="name")]
"""Every action the environment understands; composite and primitive actions join this union."""

FINAL_ACTIONS = frozenset({"done", "failed"})
"""Actions that end the episode."""
