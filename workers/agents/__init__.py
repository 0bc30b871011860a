"""The built-in agents, registered like any plugin (``scratchworld.agents`` entry points), and the
model-call record every agent's calls go through."""

from workers.agents._awm import AWMAgent
from workers.agents._llm_agent import LLMAgent
from workers.agents._model_calls import EpisodeModels, StepCalls, shared_client
from workers.agents._planner_grounder import PlannerGrounderAgent
from workers.agents._scripted import NoopAgent, OracleAgent

__all__ = [
    "AWMAgent",
    "EpisodeModels",
    "LLMAgent",
    "NoopAgent",
    "OracleAgent",
    "PlannerGrounderAgent",
    "StepCalls",
    "shared_client",
]
