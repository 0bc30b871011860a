"""What the kinds of single answers (drag, perception) share: several agents compared in one sweep (their config
section's ``agents``), and no memory across jobs or synthetic stand-in episodes, which are the task episodes' own."""

from __future__ import annotations

from pydantic import BaseModel

from scratchworld_dist.kinds.base import Kind
from scratchworld_dist.kinds.tasks import episode_settings
from scratchworld_dist.sweep import SweepConfig
from workers.agent_api import agent_class, checked_agent
from workers.contract import AgentRef, AgentUnavailableError


class AgentsSection(BaseModel):
    """The part of a single-answer kind's section this base reads: the agents it compares."""

    agents: list[AgentRef] = []


class SingleAnswerKind(Kind):
    """A kind whose jobs ask an agent one question; its section (``config_section``) has ``agents``."""

    def agents(self, config: SweepConfig) -> list[AgentRef]:
        """The agents the sweep compares: its section's ``agents``, else the config's ``agent``."""
        section = config.sections.get(self.name)
        return (section.agents if isinstance(section, AgentsSection) else []) or [config.agent]

    def check_sweep(self, config: SweepConfig) -> None:
        """No memory or synthetic episodes (``episodes.memory``, ``episodes.synthetic``, or their former keys)."""
        episodes = episode_settings(config)
        if episodes.memory is not None or episodes.synthetic is not None:
            raise ValueError(f"memory and synthetic are for task suites, not the {self.title} benchmark")

    def needs_model(self, config: SweepConfig) -> bool:
        return any(agent_class(agent.name, self.name).needs_model for agent in self.agents(config))


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
