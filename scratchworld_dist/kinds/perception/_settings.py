"""The perception kind's section of a sweep config, ``perception:``: the item kinds and the agents it compares."""

from __future__ import annotations

from pathlib import Path

from pydantic import ConfigDict, Field, field_validator

from scratchworld_dist.kinds._single_answer import AgentsSection, checked_agents
from workers.contract import AgentRef
from workers.kinds.perception import QuestionKind


class PerceptionSweep(AgentsSection):
    """The perception benchmark's own axes (``benchmark: perception``): jobs are agent x model x item x seed."""

    model_config = ConfigDict(extra="forbid")

    agents: list[AgentRef] = Field(default_factory=list)
    """The perception agents to compare in one sweep (default: the config's ``agent``); a scripted one
    (oracle, always_yes) runs once, without the models, ``llm`` once per model."""

    kinds: list[QuestionKind] = Field(default_factory=list)
    """Item kinds to run (empty: all of connection, existence and field)."""

    optional_suites: list[Path] = Field(default_factory=list)
    """More perception suites, each run when present and skipped with a notice when not (e.g. an upstream clone)."""

    @field_validator("agents")
    @classmethod
    def _known_agents(cls, agents: list[AgentRef]) -> list[AgentRef]:
        return checked_agents(agents, "perception")
