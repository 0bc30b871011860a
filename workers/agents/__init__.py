"""Agents: who decides the next action of an episode."""

from workers.agents._agent import Agent, AgentUnavailableError, ConversingAgent, NeedsEditor, agent_for
from workers.agents._llm_agent import LLMAgent
from workers.agents._scripted import NoopAgent, OracleAgent

__all__ = [
    "Agent",
    "AgentUnavailableError",
    "ConversingAgent",
    "LLMAgent",
    "NeedsEditor",
    "NoopAgent",
    "OracleAgent",
    "agent_for",
]
