"""Agents: who decides the next action of an episode."""

from workers.agents._agent import Agent, AgentUnavailableError, NeedsEditor, agent_for
from workers.agents._scripted import NoopAgent, OracleAgent

__all__ = ["Agent", "AgentUnavailableError", "NeedsEditor", "NoopAgent", "OracleAgent", "agent_for"]
