"""What the kinds of single answers (drag, perception) share in checking a sweep: several agents compared in one
sweep (their config section's ``agents``), and no memory across jobs or synthetic stand-in episodes, which are
the task episodes' own."""

from __future__ import annotations

from typing import TYPE_CHECKING

from scratchworld_dist.kinds.tasks import episode_settings
from workers.agent_api import checked_agent
from workers.contract import AgentRef, AgentUnavailableError

if TYPE_CHECKING:
    from scratchworld_dist.sweep import SweepConfig


def refuse_episode_sections(config: SweepConfig, title: str) -> None:
    """Raise ``ValueError`` when a single-answer sweep names memory or synthetic episodes (``episodes.memory``,
    ``episodes.synthetic``, or their former top-level keys)."""
    episodes = episode_settings(config)
    if episodes.memory is not None or episodes.synthetic is not None:
        raise ValueError(f"memory and synthetic are for task suites, not the {title} benchmark")


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


def section_agents(config: SweepConfig, agents: list[AgentRef]) -> list[AgentRef]:
    """The agents a section names, else the config's ``agent``."""
    return agents or [config.agent]
