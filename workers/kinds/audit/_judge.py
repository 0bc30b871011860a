"""Whether a variant the tests misjudge behaves as the golden does, judged without trusting the tests: the tests'
own run (both traced under one seed), then every episode of the task's exploration (the flag, the keys, clicks,
backdrops and messages the golden's hats listen to, answers to its questions, several seeds). A variant is
equivalent only when every run shows the golden's trace; the first run with a difference the task allows makes
it differ, with the difference and the stimulus that showed it. A difference only answers the instruction rules
out show (``ExplorationPlan.answer_domain``) is told apart: outside the task."""

from __future__ import annotations

from typing import TYPE_CHECKING

from pydantic import BaseModel, Field

from workers.contract import EvaluationSpec, ProjectLimits
from workers.kinds.audit._contract import AuditObservation, Observed, ShownBy
from workers.kinds.audit._exploration import ExplorationEpisode, ExplorationPlan
from workers.kinds.audit._golden_runs import GOLDEN_RUNS, TRACE_SEED, explore

if TYPE_CHECKING:
    from workers.evaluation import Evaluator, ObservableTrace, PageRun, TraceDifference


class Applied(BaseModel):
    index: int
    frame: int | None = None
    found: bool = True


class EpisodeOutcome(BaseModel):
    """What the page's ``explore`` runner returned: the answers it gave, when it did each stimulus."""

    answers: list[str] = Field(default_factory=list)
    answered_at: list[int | None] = Field(default_factory=list, alias="answeredAt")
    applied: list[Applied] = Field(default_factory=list)
    steps: int | None = None

    def answers_before(self, frame: int) -> list[str]:
        """The answers given before ``frame`` (all of them when their frames are unknown)."""
        if len(self.answered_at) != len(self.answers):
            return self.answers
        return [a for a, at in zip(self.answers, self.answered_at, strict=True) if at is None or at < frame]


def outcome_of(run: PageRun) -> EpisodeOutcome:
    return EpisodeOutcome.model_validate(run.outcome) if isinstance(run.outcome, dict) else EpisodeOutcome()


def last_stimulus(episode: ExplorationEpisode, outcome: EpisodeOutcome, frame: int) -> str | None:
    """The last stimulus done before ``frame`` (its effects show from the frame after it was done)."""
    done = [a for a in outcome.applied if a.frame is not None and a.frame < frame and a.index < len(episode.stimuli)]
    return episode.stimuli[done[-1].index].describe() if done else None


def ordered(plan: ExplorationPlan) -> list[ExplorationEpisode]:
    """Episodes whose answers the task allows first (a difference there decides), then the others."""
    return sorted(plan.episodes, key=lambda episode: not plan.in_task(episode.answers))


def _merged(*lists: list[str]) -> list[str]:
    return list(dict.fromkeys(answer for answers in lists for answer in answers))


def _found(
    difference: TraceDifference, shown_by: ShownBy, runs: int, truncated: bool, observed: Observed = "differs"
) -> AuditObservation:
    return AuditObservation(
        observed=observed,
        difference=difference.describe(),
        shown_by=shown_by,
        first=difference.model_dump(mode="json"),
        runs=runs,
        truncated=truncated,
    )


async def judged_by_behaviour(
    evaluator: Evaluator,
    golden: bytes,
    project: bytes,
    spec: EvaluationSpec,
    limits: ProjectLimits,
    plan: ExplorationPlan | None,
) -> AuditObservation | None:
    """The variant ``project`` against ``golden``: the tests' own run, then ``plan``'s episodes; None when not even
    the tests' run could be traced (the verdict then stands unobserved)."""
    from workers.evaluation import first_difference

    theirs = await GOLDEN_RUNS.tests_trace(evaluator, golden, spec, limits)
    ours = await evaluator.evaluate_traced(project, spec, limits, random_seed=TRACE_SEED)
    if theirs is None or ours.trace is None:
        return None
    truncated = theirs.truncated or ours.trace.truncated
    runs = 1
    difference = first_difference(theirs, ours.trace)
    if difference is not None:
        return _found(difference, ShownBy(run="tests", seed=TRACE_SEED), runs, truncated)
    outside: AuditObservation | None = None
    for episode in ordered(plan) if plan is not None else []:
        golden_run = await GOLDEN_RUNS.episode(evaluator, golden, spec, episode, limits)
        if golden_run.trace is None or golden_run.error is not None:
            continue  # the golden's own run did not finish: nothing to compare with
        run = await explore(evaluator, project, spec, episode, limits)
        found = _compared(episode, golden_run, run)
        runs += 1
        if found is None:
            continue
        difference, shown_by, trace = found
        truncated = truncated or golden_run.trace.truncated or (trace is not None and trace.truncated)
        if plan is not None and plan.in_task(shown_by.answers):
            return _found(difference, shown_by, runs, truncated)
        outside = outside or _found(difference, shown_by, runs, truncated, "outside_task")
    if outside is not None:
        return outside.model_copy(update={"runs": runs})
    return AuditObservation(observed="equivalent", runs=runs, truncated=truncated)


def _compared(
    episode: ExplorationEpisode, golden_run: PageRun, run: PageRun
) -> tuple[TraceDifference, ShownBy, ObservableTrace | None] | None:
    """The first difference of the variant's run of ``episode`` from the golden's (a run that did not finish
    where the golden's did is one, at its last frame), and the run that shows it; None when they agree."""
    from workers.evaluation import TraceDifference, first_difference

    theirs, ours = outcome_of(golden_run), outcome_of(run)
    assert golden_run.trace is not None
    if run.trace is None or run.error is not None:
        frame = golden_run.trace.steps if run.trace is None else run.trace.steps
        difference = TraceDifference(
            frame=frame, target="Stage", field="run", a="finished", b=run.error or "no trace recorded"
        )
        answers = _merged(theirs.answers, ours.answers)
        stimulus = last_stimulus(episode, ours if ours.applied else theirs, frame + 1)
        return difference, ShownBy(run=episode.name, seed=episode.seed, answers=answers, stimulus=stimulus), None
    difference = first_difference(golden_run.trace, run.trace)
    if difference is None:
        return None
    answers = _merged(theirs.answers_before(difference.frame), ours.answers_before(difference.frame))
    stimulus = last_stimulus(episode, ours, difference.frame)
    return difference, ShownBy(run=episode.name, seed=episode.seed, answers=answers, stimulus=stimulus), run.trace
