"""The agent protocol and the registry that picks one for an episode."""

from __future__ import annotations

from typing import Protocol, runtime_checkable

from workers.contract import Action, EpisodeSpec, Observation, ScratchWorldError, StepRecord, TaskPayload
from workers.editor import Editor


class AgentUnavailableError(ScratchWorldError):
    """The requested agent cannot run here (not built yet, or missing its inputs)."""


class Agent(Protocol):
    """Chooses actions; scripted agents ignore observations, model-driven ones read them."""

    observes: bool
    """Whether the environment must build an observation before each action."""

    async def act(self, observation: Observation | None) -> Action: ...


@runtime_checkable
class NeedsEditor(Protocol):
    """A privileged agent (the primitive oracle) that reads the page before its first action."""

    async def begin(self, editor: Editor) -> None: ...


@runtime_checkable
class ConversingAgent(Protocol):
    """An agent in a conversation with a model: briefed before its first action, told what each did."""

    images: dict[str, bytes]
    """Images it showed its model, by SHA-256 (kept once with the episode's result)."""

    async def brief(self, block_catalog: str | None) -> None: ...

    def after_step(self, step: StepRecord) -> StepRecord:
        """Take note of the step's outcome; return the step with what the decision cost and said."""
        ...


def agent_for(spec: EpisodeSpec, task: TaskPayload) -> Agent:
    from workers.agents._scripted import NoopAgent, OracleAgent

    if spec.agent == "oracle":
        trajectory = task.golden_trajectory
        if trajectory is None and task.golden_project is None:
            raise AgentUnavailableError(f"task {task.task_id} has neither a golden trajectory nor a golden project")
        if spec.mode == "primitive" and trajectory is not None:
            from workers.agents._primitive_oracle import PrimitiveOracle

            return PrimitiveOracle(task.initial_project, trajectory)
        return OracleAgent(task.golden_project, trajectory)
    if spec.agent == "noop":
        return NoopAgent()
    if spec.agent == "llm":
        if spec.model is None:
            raise AgentUnavailableError("agent 'llm' needs a model")
        from workers.agents._llm_agent import LLMAgent

        return LLMAgent(spec, task)
    raise AgentUnavailableError(f"agent {spec.agent!r} is not available in this build")
