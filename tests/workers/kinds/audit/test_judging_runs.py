"""How the audit's worker side reads runs (no browser: traces are data): which answers a task allows, which
episode comes first, which stimulus and answers a difference follows, what a golden's runs change, and when a
grader is vacuous."""

from __future__ import annotations

from typing import Any

import pytest
from pydantic import ValidationError

from workers.evaluation import ObservableTrace, PageRun
from workers.kinds.audit import ExplorationEpisode, ExplorationPlan, Stimulus, in_domain
from workers.kinds.audit._judge import EpisodeOutcome, _compared, last_stimulus, ordered
from workers.kinds.audit._vacuity import changed_fields, observes, sprite_of, vacuity


@pytest.mark.parametrize(
    ("answer", "allowed"),
    [
        ("3", {"any", "text", "numbers", "integers"}),
        ("-2.5", {"any", "text", "numbers"}),
        (" 1e3 ", {"any", "text", "numbers"}),
        ("Dog", {"any", "text", "words"}),
        ("a b", {"any", "text", "words"}),
        ("", {"any"}),
        ("   ", {"any"}),
        ("3 apples", {"any", "text", "words"}),
    ],
)
def test_an_answer_is_in_the_domains_that_allow_it(answer: str, allowed: set[str]) -> None:
    domains = {"any", "text", "numbers", "integers", "words"}
    assert {domain for domain in domains if in_domain(answer, domain)} == allowed  # type: ignore[arg-type]


def episode(name: str, answers: list[str], seed: int = 1) -> ExplorationEpisode:
    stimuli = [Stimulus(at_ms=0, kind="green_flag"), Stimulus(at_ms=1500, kind="key", name="space", hold_ms=300)]
    return ExplorationEpisode(name=name, seed=seed, stimuli=stimuli, answers=answers, span_ms=8000)


def test_episodes_whose_answers_the_task_allows_come_first_and_stimuli_keep_time_order() -> None:
    plan = ExplorationPlan(
        episodes=[episode("empty", [""]), episode("words", ["hi"]), episode("numbers", ["3", "4"])],
        answer_domain="numbers",
    )
    assert [e.name for e in ordered(plan)] == ["numbers", "empty", "words"]
    assert plan.in_task(["3", "-1"]) and not plan.in_task(["3", ""])
    with pytest.raises(ValidationError, match="time order"):
        ExplorationEpisode(
            name="x", seed=1, span_ms=1000,
            stimuli=[Stimulus(at_ms=500, kind="green_flag"), Stimulus(at_ms=100, kind="green_flag")],
        )  # fmt: skip
    with pytest.raises(ValidationError, match="time order"):
        ExplorationEpisode(name="x", seed=1, span_ms=1000, stimuli=[Stimulus(at_ms=2000, kind="green_flag")])


def test_a_difference_names_the_stimulus_before_it_and_only_the_answers_given_before_it() -> None:
    run = episode("e", ["3", "hello"])
    outcome = EpisodeOutcome.model_validate(
        {
            "answers": ["3", "hello"],
            "answeredAt": [5, 60],
            "applied": [{"index": 0, "frame": 1}, {"index": 1, "frame": 45}],
        }
    )
    assert last_stimulus(run, outcome, 45) == "green flag at 0.0 s"  # the key's effects show from frame 46
    assert last_stimulus(run, outcome, 46) == "key 'space' at 1.5 s"
    assert last_stimulus(run, outcome, 1) is None
    assert outcome.answers_before(50) == ["3"] and outcome.answers_before(61) == ["3", "hello"]


def trace(*frames: dict[str, Any], steps: int = 100) -> ObservableTrace:
    return ObservableTrace.model_validate({"frames": list(frames), "steps": steps, "chars": 10})


START = {"frame": 0, "targets": {"Stage": {"costume": "b"}, "Cat": {"x": 0, "bubble": None}}}


def test_a_difference_after_an_answer_the_task_rules_out_is_named_with_that_answer() -> None:
    run = episode("seed 2, answers: empty", ["", ""])
    outcome = {"answers": ["", ""], "answeredAt": [10, 40], "applied": [{"index": 0, "frame": 0}]}
    golden = PageRun(
        trace=trace(START, {"frame": 11, "targets": {"Cat": {"bubble": ["say", "nothing"]}}}), outcome=outcome
    )
    variant = PageRun(
        trace=trace(START, {"frame": 11, "targets": {"Cat": {"bubble": ["say", "NOTHING"]}}}), outcome=outcome
    )
    found = _compared(run, golden, variant)
    assert found is not None
    difference, shown_by, _ = found
    assert (difference.frame, difference.target, difference.field) == (11, "Cat", "bubble")
    assert shown_by.answers == [""] and shown_by.seed == 1 and shown_by.stimulus == "green flag at 0.0 s"
    assert "exploration 'seed 2, answers: empty'" in shown_by.describe() and "after green flag" in shown_by.describe()
    plan = ExplorationPlan(episodes=[run], answer_domain="numbers")
    assert not plan.in_task(shown_by.answers)  # the empty answer: outside a task that asks for numbers
    assert _compared(run, golden, golden) is None
    # A variant whose run did not finish where the golden's did differs there.
    broken = PageRun(trace=None, error="the run blocked the page", outcome=None)
    found = _compared(run, golden, broken)
    assert found is not None and found[0].field == "run" and found[0].b == "the run blocked the page"


def test_what_a_golden_changes_folds_clones_into_their_sprite_and_counts_comings_and_goings() -> None:
    seen = trace(
        START,
        {"frame": 3, "targets": {"Cat": {"x": 10}, "Cat#1": {"x": 5, "y": 1}, "Stage": {"var:s": ["s", "1", False]}}},
        {"frame": 9, "targets": {}, "removed": ["Cat#1"]},
    )
    assert changed_fields(seen) == {("Cat", "x"), ("Cat", "y"), ("Cat", "present"), ("Stage", "var:s")}
    assert sprite_of("Cat#12") == "Cat" and sprite_of("A#b") == "A#b" and sprite_of("Stage") == "Stage"
    changes = changed_fields(seen)
    assert observes([("Cat", "x")], changes) and observes([("*", "present")], changes)
    assert not observes([("Cat", "bubble"), ("Dog", "x"), ("*", "question")], changes)
    assert vacuity(False, [("Cat", "x")], changes) == "never_starts"
    assert vacuity(True, [("Cat", "bubble")], changes) == "observes_nothing"
    assert vacuity(True, [("Stage", "var:s")], changes) is None
