"""Scripted agents that need no model: reference points for every sweep.

The oracle shows what the harness scores for a correct solution (it must be 100% on a valid
suite); the no-op agent shows what the untouched initial project scores. Both are registered
through the public agent API like any plugin; the oracle is its one privileged user.
"""

from __future__ import annotations

from typing import ClassVar

from workers.agent_api import AgentBase, StepResult, TaskContext
from workers.agents._primitive_oracle import PrimitiveOracle
from workers.contract import Action, AgentUnavailableError, Done, LoadProject, Observation


class OracleAgent(AgentBase):
    """Solves the task from its golden solution.

    Composite mode replays the golden trajectory through the semantic API; primitive mode acts it
    out as real gestures (``PrimitiveOracle``). A task without a trajectory (upstream suites) gets
    its golden project loaded instead, which checks the evaluation but not the editing means.
    """

    observes: ClassVar[bool] = False
    privileged: ClassVar[bool] = True

    async def start(self, context: TaskContext) -> None:
        solution = context.privileges
        trajectory = solution.golden_trajectory
        self._gestures: PrimitiveOracle | None = None
        if context.mode == "primitive" and trajectory is not None:
            self._gestures = PrimitiveOracle(solution.initial_project, trajectory)
            await self._gestures.begin(solution.editor)
            return
        if trajectory is not None:
            self._plan: list[Action] = [*trajectory, Done()]
        elif solution.golden_project is not None:
            self._plan = [LoadProject(sb3=solution.golden_project), Done()]
        else:
            raise AgentUnavailableError(f"task {context.task_id} has neither a golden trajectory nor a golden project")

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        if self._gestures is not None:
            return await self._gestures.act(None)
        return self._plan.pop(0) if len(self._plan) > 1 else self._plan[0]


class NoopAgent(AgentBase):
    """Declares the task done without touching the project."""

    observes: ClassVar[bool] = False

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        return Done()
