"""The drag kind's section of a sweep config, ``drag:``: its own axes and the agents it compares."""

from __future__ import annotations

from pathlib import Path

from pydantic import ConfigDict, Field, field_validator

from scratchworld_dist.kinds._single_answer import AgentsSection, checked_agents
from workers.agent_api import DragSetting
from workers.contract import AgentRef
from workers.kinds.drag import DragType


class DragSweep(AgentsSection):
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
