"""The agent protocol and the registry that picks one for an episode."""

from __future__ import annotations

from typing import Protocol

from workers._actions import Action
from workers._episode import EpisodeSpec, TaskPayload
from workers._errors import ScratchWorldError


class AgentUnavailableError(ScratchWorldError):
    """The requested agent cannot run here (not built yet, or missing its inputs)."""


class Agent(Protocol):
    """Chooses actions; scripted agents ignore observations, model-driven ones read them."""

    observes: bool
    """Whether the environment must build an observation before each action."""

    async def act(self, observation: str | None) -> Action: ...


def agent_for(spec: EpisodeSpec, task: TaskPayload) -> Agent:
    from workers.agents._scripted import NoopAgent, OracleAgent

    if spec.agent == "oracle":
        trajectory = task.golden_trajectory if spec.mode == "composite" else None
        if trajectory is None and task.golden_project is None:
            raise AgentUnavailableError(f"task {task.task_id} has neither a golden trajectory nor a golden project")
        return OracleAgent(task.golden_project, trajectory)
    if spec.agent == "noop":
        return NoopAgent()
    raise AgentUnavailableError(f"agent {spec.agent!r} is not available in this build")
