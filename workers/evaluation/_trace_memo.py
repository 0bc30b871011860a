"""Traced runs an evaluator made, kept to be used again: a grader audit traces the golden beside every variant
the tests misjudge, under one seed, and it is the same run each time.

A traced run on the virtual clock with a seeded ``Math.random`` and the script's own inputs is reproducible (the
same trace twice: tests/workers/evaluation/test_observable_trace_verdicts.py), so one run per worker serves
every variant of a task. Only a caller that asks reuses one (``Evaluator.evaluate_traced(..., reuse=True)``);
a run without a trace (a page killed for blocking) is not kept, and two asked for at once both run.
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict

from workers.contract import EvaluationSpec, ProjectLimits
from workers.evaluation._trace import TracedEvaluation

KEPT_RUNS = 8
"""Traced runs kept, the last used first (a worker's jobs come task by task: a golden or two at a time)."""


def run_key(project: bytes, spec: EvaluationSpec, limits: ProjectLimits, max_chars: int) -> str:
    """What a traced run's result depends on: the project's bytes, the spec (its seed included), limits and cap."""
    parts = [hashlib.sha256(project).hexdigest(), spec.model_dump_json(), limits.model_dump_json(), str(max_chars)]
    return hashlib.sha256("\n".join(parts).encode()).hexdigest()


class TraceMemo:
    """The last ``size`` traced runs that recorded a trace, by ``run_key``."""

    def __init__(self, size: int = KEPT_RUNS) -> None:
        self.size = size
        self._runs: OrderedDict[str, TracedEvaluation] = OrderedDict()
        self.reused = 0
        """Runs served from the memo instead of a page."""

    def get(self, key: str) -> TracedEvaluation | None:
        kept = self._runs.get(key)
        if kept is not None:
            self._runs.move_to_end(key)
            self.reused += 1
        return kept

    def keep(self, key: str, run: TracedEvaluation) -> None:
        if run.trace is None:
            return
        self._runs[key] = run
        self._runs.move_to_end(key)
        while len(self._runs) > self.size:
            self._runs.popitem(last=False)
