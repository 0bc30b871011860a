"""The public agent API: everything a plugin needs to bring its own agent, and nothing heavier.

Importing it loads pydantic and the standard library only (no Playwright, OpenCV or Ray). An
agent implements ``Agent`` (or subclasses ``AgentBase``): ``start(context)``, then
``act(observation, last)`` per step, then ``finish(end)``. It calls models through
``context.model()``, so retries, rate limits, costs and the trajectory log apply to it too, and
is named in a sweep config as ``agent: {name: package.module:Class, params: {...}}`` or by an
entry point of the ``scratchworld.agents`` group. See README, "Write your own agent".
"""

from workers.agent_api._agent import Agent, AgentBase, EpisodeEnd, NoParams, StepResult
from workers.agent_api._context import ModelHandle, ModelReply, Privileges, TaskContext
from workers.agent_api._memory import AgentMemory, InductionRequest, LearningAgent, MemoryUpdate
from workers.agent_api._registry import (
    ENTRY_POINT_GROUP,
    agent_class,
    agent_code,
    agent_params,
    build_agent,
    extra_models,
    registered_agents,
)
from workers.contract import (
    Action,
    ActionEnvelope,
    ActionFailure,
    AgentRef,
    AgentUnavailableError,
    CompositeAction,
    CompositeObservation,
    Done,
    Element,
    Failed,
    InvalidReply,
    LoadProject,
    MemoryItem,
    Mode,
    ModelCallError,
    ModelSpec,
    Observation,
    PrimitiveAction,
    PrimitiveObservation,
    TargetName,
    composite_action,
    primitive_action,
)

__all__ = [
    "ENTRY_POINT_GROUP",
    "Action",
    "ActionEnvelope",
    "ActionFailure",
    "Agent",
    "AgentBase",
    "AgentMemory",
    "AgentRef",
    "AgentUnavailableError",
    "CompositeAction",
    "CompositeObservation",
    "Done",
    "Element",
    "EpisodeEnd",
    "Failed",
    "InductionRequest",
    "InvalidReply",
    "LearningAgent",
    "LoadProject",
    "MemoryItem",
    "MemoryUpdate",
    "Mode",
    "ModelCallError",
    "ModelHandle",
    "ModelReply",
    "ModelSpec",
    "NoParams",
    "Observation",
    "PrimitiveAction",
    "PrimitiveObservation",
    "Privileges",
    "StepResult",
    "TargetName",
    "TaskContext",
    "agent_class",
    "agent_code",
    "agent_params",
    "build_agent",
    "composite_action",
    "extra_models",
    "primitive_action",
    "registered_agents",
]
