"""Scripted agents that need no model: reference points for every sweep.

The oracle shows what the harness scores for a correct project (it must be 100% on a valid
suite, in every mode); the no-op agent shows what the untouched initial project scores.
"""

from __future__ import annotations

from workers._actions import Action, Done, LoadProject


class OracleAgent:
    """Loads the task's golden project, then declares it done."""

    observes = False

    def __init__(self, golden_project: bytes) -> None:
        self._plan: list[Action] = [LoadProject(sb3=golden_project), Done()]

    async def act(self, observation: str | None) -> Action:
        return self._plan.pop(0) if len(self._plan) > 1 else self._plan[0]


class NoopAgent:
    """Declares the task done without touching the project."""

    observes = False

    async def act(self, observation: str | None) -> Action:
        return Done()
