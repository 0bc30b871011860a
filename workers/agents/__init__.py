"""The built-in agents, registered like any plugin (``scratchworld.agents`` entry points), the
model-call record every agent's calls go through, and the screen and coordinate systems models answer in
(the drag benchmark's agents share them)."""

from workers.agents._awm import AWMAgent
from workers.agents._coordinates import SCREEN, coordinate_system, model_space
from workers.agents._llm_agent import LLMAgent
from workers.agents._model_calls import EpisodeModels, StepCalls, shared_client
from workers.agents._planner_grounder import PlannerGrounderAgent
from workers.agents._prompts import PRIMITIVE_POSITIONS
from workers.agents._scripted import NoopAgent, OracleAgent

__all__ = [
    "PRIMITIVE_POSITIONS",
    "SCREEN",
    "AWMAgent",
    "EpisodeModels",
    "LLMAgent",
    "NoopAgent",
    "OracleAgent",
    "PlannerGrounderAgent",
    "StepCalls",
    "coordinate_system",
    "model_space",
    "shared_client",
]
