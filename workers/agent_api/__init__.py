"""The public agent API: everything a plugin needs to bring its own agent, and nothing heavier.

Importing it loads pydantic and the standard library only (no Playwright, OpenCV or Ray). An
agent implements ``Agent`` (or subclasses ``AgentBase``): ``start(context)``, then
``act(observation, last)`` per step, then ``finish(end)``. It calls models through
``context.model()``, so retries, rate limits, costs and the trajectory log apply to it too, and
is named in a sweep config as ``agent: {name: package.module:Class, params: {...}}`` or by an
entry point of the ``scratchworld.agents`` group. Agents of the drag and perception benchmarks answer one
question (``DragAgentBase``, ``PerceptionAgentBase``) and register in groups of their own. See docs/own-agent.md,
"Write your own agent".
"""

from workers.agent_api._agent import Agent, AgentBase, EpisodeEnd, NoParams, StepResult
from workers.agent_api._context import ModelHandle, ModelReply, Privileges, TaskContext
from workers.agent_api._memory import AgentMemory, InductionRequest, LearningAgent, MemoryUpdate
from workers.agent_api._registry import (
    agent_class,
    agent_code,
    agent_kinds,
    agent_params,
    build_agent,
    checked_agent,
    code_mismatch,
    extra_models,
    is_privileged,
    registered_agents,
)
from workers.agent_api._single_step import (
    DragAgentBase,
    DragAnswer,
    DragQuestion,
    ModelSource,
    PerceptionAgentBase,
    PerceptionQuestion,
    SingleStepAgent,
)
from workers.contract import (
    Action,
    ActionEnvelope,
    ActionFailure,
    AgentRef,
    AgentUnableError,
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
    "Action",
    "ActionEnvelope",
    "ActionFailure",
    "Agent",
    "AgentBase",
    "AgentMemory",
    "AgentRef",
    "AgentUnableError",
    "AgentUnavailableError",
    "CompositeAction",
    "CompositeObservation",
    "Done",
    "DragAgentBase",
    "DragAnswer",
    "DragQuestion",
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
    "ModelSource",
    "ModelSpec",
    "NoParams",
    "Observation",
    "PerceptionAgentBase",
    "PerceptionQuestion",
    "PrimitiveAction",
    "PrimitiveObservation",
    "Privileges",
    "SingleStepAgent",
    "StepResult",
    "TargetName",
    "TaskContext",
    "agent_class",
    "agent_code",
    "agent_kinds",
    "agent_params",
    "build_agent",
    "checked_agent",
    "code_mismatch",
    "composite_action",
    "extra_models",
    "is_privileged",
    "primitive_action",
    "registered_agents",
]
