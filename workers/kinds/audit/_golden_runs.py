"""The golden's runs a worker keeps: every variant of a task is compared with the same runs of its golden (its
tests' own trace, each episode of the task's exploration), deterministic in virtual time under their seeds, so a
worker makes each once and keeps it for the task's next variants."""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from collections.abc import Awaitable, Callable
from typing import TYPE_CHECKING, Any, Protocol, TypeVar

from workers.contract import EvaluationSpec, ProjectLimits
from workers.kinds.audit._exploration import ExplorationEpisode

if TYPE_CHECKING:
    from workers.evaluation import Evaluator, ObservableTrace, PageRun, TracedEvaluation

TRACE_SEED = 0
"""The seed of ``Math.random`` the tests' own runs are traced under."""

EXPLORATION_MARGIN_S = 10.0
"""Simulated seconds an episode's page run may take past its span before the page stops it."""

KEPT = 128
"""Golden runs a worker keeps (the least recently used go first): a few tasks' explorations."""


class _Traced(Protocol):
    @property
    def trace(self) -> ObservableTrace | None: ...


Run = TypeVar("Run", bound=_Traced)


def exploration_spec(spec: EvaluationSpec, episode: ExplorationEpisode) -> EvaluationSpec:
    """The task's conditions for an episode, its timeout the episode's span and a margin."""
    return spec.model_copy(update={"timeout_s": episode.span_ms / 1000 + EXPLORATION_MARGIN_S})


async def explore(
    evaluator: Evaluator, project: bytes, spec: EvaluationSpec, episode: ExplorationEpisode, limits: ProjectLimits
) -> PageRun:
    """``project`` run through ``episode`` under the task's conditions."""
    from workers.evaluation import explored

    return await explored(evaluator, project, exploration_spec(spec, episode), episode.timeline(), episode.seed, limits)


class GoldenRuns:
    """Finished runs of goldens by what made them (the golden's bytes, the conditions, the run); a run that
    recorded no trace is not kept (the next variant tries again)."""

    def __init__(self, kept: int = KEPT) -> None:
        self.kept = kept
        self._runs: OrderedDict[str, Any] = OrderedDict()

    async def _get(self, parts: tuple[bytes | str, ...], make: Callable[[], Awaitable[Run]]) -> Run:
        digest = hashlib.sha256()
        for part in parts:
            data = part.encode() if isinstance(part, str) else part
            digest.update(len(data).to_bytes(8, "big") + data)
        key = digest.hexdigest()
        if key in self._runs:
            self._runs.move_to_end(key)
            found: Run = self._runs[key]
            return found
        made = await make()
        if made.trace is not None:
            self._runs[key] = made
            while len(self._runs) > self.kept:
                self._runs.popitem(last=False)
        return made

    async def tests_trace(
        self, evaluator: Evaluator, golden: bytes, spec: EvaluationSpec, limits: ProjectLimits
    ) -> ObservableTrace | None:
        """The trace of the task's tests run on the golden under ``TRACE_SEED`` (as ``evaluate_traced``)."""

        async def make() -> TracedEvaluation:
            return await evaluator.evaluate_traced(golden, spec, limits, random_seed=TRACE_SEED)

        made = await self._get((b"tests", golden, spec.model_dump_json(), limits.model_dump_json()), make)
        return made.trace

    async def episode(
        self,
        evaluator: Evaluator,
        golden: bytes,
        spec: EvaluationSpec,
        episode: ExplorationEpisode,
        limits: ProjectLimits,
    ) -> PageRun:
        """The golden run through ``episode``."""

        async def make() -> PageRun:
            return await explore(evaluator, golden, spec, episode, limits)

        parts = (b"episode", golden, spec.model_dump_json(), episode.model_dump_json(), limits.model_dump_json())
        return await self._get(parts, make)


GOLDEN_RUNS = GoldenRuns()
"""This worker process's golden runs."""
