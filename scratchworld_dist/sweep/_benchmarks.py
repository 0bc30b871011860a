"""The sections of a sweep config that belong to one diagnostic benchmark: ``drag:`` and ``perception:``."""

from __future__ import annotations

from pathlib import Path

from pydantic import BaseModel, ConfigDict, Field, field_validator

from workers.agent_api import checked_agent
from workers.contract import AgentRef, AgentUnavailableError, DragSetting, DragType, PerceptionKind


def checked_agents(agents: list[AgentRef], benchmark: str) -> list[AgentRef]:
    """``agents`` when each is an agent of ``benchmark`` with valid params and their labels are distinct."""
    for agent in agents:
        try:
            checked_agent(agent, benchmark)
        except AgentUnavailableError as exc:
            raise ValueError(str(exc)) from None
    labels = [agent.display for agent in agents]
    if len(set(labels)) != len(labels):
        raise ValueError(f"two {benchmark} agents share a name: give them distinct labels")
    return agents


class DragSweep(BaseModel):
    """The drag benchmark's own axes (``benchmark: drag``): jobs are model x setting x task x seed."""

    model_config = ConfigDict(extra="forbid")

    settings: list[DragSetting] = Field(default_factory=lambda: ["baseline"], min_length=1)
    types: list[DragType] = Field(default_factory=list)
    """Task types to run (empty: both)."""

    agents: list[AgentRef] = Field(default_factory=list)
    """The drag agents to compare in one sweep (default: the config's ``agent``); a scripted one runs once,
    without the models, a model-driven one once per model."""

    element_list: bool = False
    """Show primitive mode's element list with the screenshot, and accept ``<index>`` answers."""

    optional_suites: list[Path] = Field(default_factory=list)
    """More drag suites, each run when present and skipped with a notice when not (e.g. an upstream clone)."""

    @field_validator("settings")
    @classmethod
    def _distinct(cls, value: list[DragSetting]) -> list[DragSetting]:
        if len(set(value)) != len(value):
            raise ValueError("settings must be distinct")
        return value

    @field_validator("agents")
    @classmethod
    def _known_agents(cls, agents: list[AgentRef]) -> list[AgentRef]:
        return checked_agents(agents, "drag")


class PerceptionSweep(BaseModel):
    """The perception benchmark's own axes (``benchmark: perception``): jobs are agent x model x item x seed."""

    model_config = ConfigDict(extra="forbid")

    agents: list[AgentRef] = Field(default_factory=list)
    """The perception agents to compare in one sweep (default: the config's ``agent``); a scripted one
    (oracle, always_yes) runs once, without the models, ``llm`` once per model."""

    kinds: list[PerceptionKind] = Field(default_factory=list)
    """Item kinds to run (empty: all of connection, existence and field)."""

    optional_suites: list[Path] = Field(default_factory=list)
    """More perception suites, each run when present and skipped with a notice when not (e.g. an upstream clone)."""

    @field_validator("agents")
    @classmethod
    def _known_agents(cls, agents: list[AgentRef]) -> list[AgentRef]:
        return checked_agents(agents, "perception")
