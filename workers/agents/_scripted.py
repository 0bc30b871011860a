"""Scripted agents that need no model: reference points for every sweep.

The oracle shows what the harness scores for a correct solution (it must be 100% on a valid
suite); the no-op agent shows what the untouched initial project scores.
"""

from __future__ import annotations

from workers.contract import Action, CompositeAction, Done, LoadProject


class OracleAgent:
    """Replays the task's golden trajectory through the composite API, then declares it done.

    A task without a trajectory (upstream suites) gets its golden project loaded instead, which
    checks the evaluation but not the editing API.
    """

    observes = False

    def __init__(self, golden_project: bytes | None, trajectory: list[CompositeAction] | None = None) -> None:
        if trajectory is not None:
            self._plan: list[Action] = [*trajectory, Done()]
        elif golden_project is not None:
            self._plan = [LoadProject(sb3=golden_project), Done()]
        else:
            raise ValueError("the oracle needs a golden trajectory or a golden project")

    async def act(self, observation: object) -> Action:
        return self._plan.pop(0) if len(self._plan) > 1 else self._plan[0]


class NoopAgent:
    """Declares the task done without touching the project."""

    observes = False

    async def act(self, observation: object) -> Action:
        return Done()
