"""Whether a task's tests judge anything at all, found on its golden: tests that never start the program (no
green flag, no script started: ``never_starts``), or that read nothing the program changes (``observes_nothing``:
no sprite, variable, list, bubble, question, sound or pen field they read is one the golden changes in its
exploration or its tests' run). Such a grader passes every program; the report names it before its score."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from workers.contract import EvaluationSpec, ProjectLimits
from workers.kinds.audit._contract import GraderCheck, Vacuity
from workers.kinds.audit._exploration import ExplorationPlan
from workers.kinds.audit._golden_runs import GOLDEN_RUNS, TRACE_SEED

if TYPE_CHECKING:
    from workers.evaluation import Evaluator, ObservableTrace

Field = tuple[str, str]
"""(target, field): a sprite by name (its clones folded into it), ``Stage``, or ``*`` (any) in a read."""


def sprite_of(key: str) -> str:
    """The target a trace key names: a clone ``Cat#3`` is its sprite ``Cat``."""
    name, mark, number = key.rpartition("#")
    return name if mark and number.isdigit() else key


def changed_fields(trace: ObservableTrace) -> set[Field]:
    """The fields the trace shows changing after the run's start (a target that comes or goes: ``present``)."""
    changed: set[Field] = set()
    start = next((frame for frame in trace.frames if frame.frame == 0), None)
    there = set(start.targets) if start is not None else set()
    for frame in trace.frames:
        if frame.frame == 0:
            continue
        for key, fields in frame.targets.items():
            changed.update((sprite_of(key), name) for name in fields)
            if key not in there:
                changed.add((sprite_of(key), "present"))
                there.add(key)
        changed.update((sprite_of(key), "present") for key in frame.removed)
    return changed


def observes(reads: Iterable[Field], changes: set[Field]) -> bool:
    """Whether any field read is one that changes (a read of ``*`` matches the field on any target)."""
    return any(
        (target, field) in changes or (target == "*" and any(name == field for _, name in changes))
        for target, field in reads
    )


def vacuity(started: bool, reads: Iterable[Field], changes: set[Field]) -> Vacuity | None:
    if not started:
        return "never_starts"
    return None if observes(reads, changes) else "observes_nothing"


async def grader_check(
    evaluator: Evaluator, golden: bytes, spec: EvaluationSpec, limits: ProjectLimits, plan: ExplorationPlan | None
) -> GraderCheck | None:
    """What the tests do with the golden: the tests' run noting their reads, and the fields the golden's runs
    change (its exploration's and the tests' run's); None when the tests' run could not be observed."""
    from workers.evaluation import observed_tests_run

    observed = await observed_tests_run(evaluator, golden, spec, TRACE_SEED, limits)
    if observed.reads is None:
        return None
    changes = changed_fields(observed.trace) if observed.trace is not None else set()
    for episode in plan.episodes if plan is not None else []:
        run = await GOLDEN_RUNS.episode(evaluator, golden, spec, episode, limits)
        if run.trace is not None:
            changes |= changed_fields(run.trace)
    reads = sorted(set(observed.reads.reads))
    return GraderCheck(
        started=observed.reads.started,
        threads=observed.reads.threads,
        reads=reads,
        changes=sorted(changes),
        vacuous=vacuity(observed.reads.started, reads, changes),
    )
