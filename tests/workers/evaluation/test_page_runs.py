"""Runs that judge a grader rather than a project: the page's ``explore`` runner (a timeline of stimuli and
answers, in virtual time, seeded) and a task's tests run while the page notes what they read. Hand-made projects
in a real page: every kind of stimulus reaches the program, an exploration is the same run twice under one seed
(and another under another seed), a bad timeline is refused in one line, the reads are the script's own (not what
the VM reads for it), and the page is left to serve the next evaluation."""

from __future__ import annotations

import pytest

from scratchworld_dist.sb3 import Project, backdrop_costume, block, circle_costume
from workers.contract import EvaluationSpec
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator, ObservableTrace, first_difference, observed_tests_run
from workers.evaluation import explored as explore_page

pytestmark = pytest.mark.browser

NOTHING = "module.exports = async () => ({details: [{name: 'unused', passed: true}]});"
SPEC = EvaluationSpec(script_name="unused.js", script_source=NOTHING, timeout_s=30, clock="virtual")

TIMELINE = {
    "stimuli": [
        {"atMs": 0, "kind": "green_flag"},
        {"atMs": 1000, "kind": "key", "name": "space", "holdMs": 200},
        {"atMs": 1500, "kind": "click", "name": "Cat"},
        {"atMs": 2000, "kind": "broadcast", "name": "ping"},
        {"atMs": 2500, "kind": "backdrop", "name": "night"},
    ],
    "answers": ["7"],
    "answerDelayMs": 100,
    "spanMs": 3500,
}


def explorable() -> bytes:
    """Cat answers to the flag (a random x, a question, the answer said), a key, a click, a message, a backdrop."""
    project = Project()
    project.stage.costumes.append(backdrop_costume("night", "#002"))
    project.stage.variable("score", 0)
    cat = project.sprite("Cat", costume=circle_costume("a", 10, "#36c"))
    cat.script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="score", VALUE=0),
        block("motion_setx", X=block("operator_random", FROM=-100, TO=100)),
        block("sensing_askandwait", QUESTION="number?"),
        block("looks_say", MESSAGE=block("sensing_answer")),
    )
    cat.script(block("event_whenkeypressed", KEY_OPTION="space"), block("motion_changeyby", DY=10))
    cat.script(block("event_whenthisspriteclicked"), block("motion_turnright", DEGREES=15))
    cat.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="ping"),
        block("data_changevariableby", VARIABLE="score", VALUE=1),
    )
    cat.script(block("event_whenbackdropswitchesto", BACKDROP="night"), block("looks_setsizeto", SIZE=50))
    return project.to_sb3()


def last(trace: ObservableTrace, target: str, field: str) -> object:
    """The field's value at the end of the run."""
    return [frame.targets[target][field] for frame in trace.frames if field in frame.targets.get(target, {})][-1]


async def test_every_stimulus_reaches_the_program_and_a_seed_gives_the_same_run(session: BrowserSession) -> None:
    project = explorable()
    async with EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        first = await explore_page(evaluator, project, SPEC, TIMELINE, seed=5)
        again = await explore_page(evaluator, project, SPEC, TIMELINE, seed=5)
        other = await explore_page(evaluator, project, SPEC, TIMELINE, seed=6)
        assert pool.discarded == {} and pool.reused >= 2  # a page explored serves the next run
    for run in (first, again, other):
        assert run.error is None and run.trace is not None, run.error
    assert first.trace is not None and again.trace is not None and other.trace is not None
    assert first.outcome == again.outcome and first.trace.frames == again.trace.frames  # the same run twice
    assert first_difference(first.trace, again.trace) is None
    found = first_difference(first.trace, other.trace)  # another seed, another random x
    assert found is not None and (found.target, found.field) == ("Cat", "x")
    outcome = first.outcome
    assert isinstance(outcome, dict) and outcome["answers"] == ["7"]
    applied = outcome["applied"]
    assert [a["index"] for a in applied] == [0, 1, 2, 3, 4] and all(a["found"] for a in applied)
    frames = [a["frame"] for a in applied]
    assert frames == sorted(frames) and 25 <= frames[1] <= 35  # the key at 1 s: some 30 frames in
    trace = first.trace
    assert last(trace, "Cat", "bubble") == ["say", "7"]  # the question answered, the answer said
    assert last(trace, "Cat", "y") == 10  # the key
    assert last(trace, "Cat", "direction") == 105  # the click
    assert last(trace, "Stage", "costume") == "night" and last(trace, "Cat", "size") == 50  # the backdrop
    assert last(trace, "Stage", "var:variable-Stage-score") == ["score", "1", False]  # the message


@pytest.mark.parametrize(
    ("change", "says"),
    [
        ({"spanMs": 0}, "explore: spanMs must be an integer"),
        ({"stimuli": [{"atMs": 0, "kind": "jump"}]}, "explore: stimuli[0].kind must be one of"),
        ({"stimuli": [{"atMs": 10, "kind": "green_flag"}, {"atMs": 5, "kind": "green_flag"}]}, "stimuli[1].atMs"),
        ({"stimuli": [{"atMs": 0, "kind": "key"}]}, "stimuli[0] names nothing to act on"),
        ({"answers": [3]}, "each answer must be a text"),
    ],
)
async def test_a_bad_timeline_is_refused_in_one_line(change: dict, says: str, evaluator: Evaluator) -> None:
    run = await explore_page(evaluator, explorable(), SPEC, {**TIMELINE, **change}, seed=0)
    assert run.error is not None and says in run.error and "\n" not in run.error
    assert run.trace is None or run.trace.steps == 0  # refused before anything ran


READER = """
module.exports = async (vm) => {
  const said = [];
  vm.runtime.on('SAY', (target, type, text) => said.push(text));
  vm.runtime.stopAll();
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 500));
  const cat = vm.runtime.targets.find((t) => t.isOriginal && t.getName() === 'Cat');
  const score = Object.values(vm.runtime.getTargetForStage().variables).find((v) => v.name === 'score');
  const seen = [cat.x, score.value];
  vm.runtime.stopAll();
  return {details: [{name: 'read', passed: seen.length === 2 && said.length >= 0}]};
};
"""

IDLE = """
module.exports = async (vm) => {
  vm.runtime.stopAll();
  await new Promise((resolve) => setTimeout(resolve, 200));
  return {details: [{name: 'idle', passed: true}]};
};
"""


async def test_the_reads_are_the_scripts_own_and_a_script_that_starts_nothing_is_seen(session: BrowserSession) -> None:
    project = explorable()
    async with EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        reader = await observed_tests_run(evaluator, project, SPEC.model_copy(update={"script_source": READER}), 0)
        idle = await observed_tests_run(evaluator, project, SPEC.model_copy(update={"script_source": IDLE}), 0)
        assert pool.discarded == {}  # the hooks are put back: the page serves again
    assert reader.reads is not None and idle.reads is not None
    assert reader.reads.started and reader.reads.flags == 1 and reader.reads.threads >= 1
    reads = set(reader.reads.reads)
    assert {("Cat", "x"), ("Stage", "var:variable-Stage-score"), ("*", "bubble")} <= reads
    # Stopping clears effects and starting moves Cat, but the VM did the reading, not the script.
    assert ("Cat", "effects") not in reads and ("Cat", "y") not in reads
    assert reader.trace is not None and reader.trace.steps > 0
    assert not idle.reads.started and idle.reads.reads == [] and idle.reads.threads == 0
