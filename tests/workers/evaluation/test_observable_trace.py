"""The observable trace: what a user could see and hear of a run, frame by frame, and where two runs differ.

Hand-made projects, each a golden and a variant wrong in one small way, evaluated by one script (green
flag, then 1.5 s of virtual time) with the trace recorded: every kind of observation shows up as the
first difference, named by frame, target and field; what a user cannot see (a variable's new name, a
hidden helper variable) leaves the traces equal; the same seed gives the same trace.
"""

from __future__ import annotations

from typing import Any

import pytest

from scratchworld_dist.sb3 import Block, Project, Sb3Archive, block, circle_costume
from tests.support.projects import with_sound
from workers.contract import EvaluationSpec
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator, ObservableTrace, TracedEvaluation, TraceDifference, first_difference

pytestmark = pytest.mark.browser

RUN_A_WHILE = """
module.exports = async (vm) => {
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 1500));
  return {details: [{name: 'ran', passed: true}]};
};
"""

SPEC = EvaluationSpec(script_name="run.js", script_source=RUN_A_WHILE, timeout_s=20, clock="virtual")


def cat(*script: Block, **sprite: Any) -> Project:
    """A project whose sprite Cat runs ``script`` on the green flag (with a score, an items list, two costumes)."""
    project = Project()
    project.stage.variable("score", 0).list("items", [])
    costumes = [circle_costume("a", 10, "#36c"), circle_costume("b", 12, "#c63")]
    project.sprite("Cat", costume=costumes, **sprite).script(block("event_whenflagclicked"), *script)
    return project


async def traced(evaluator: Evaluator, project: Project | bytes, seed: int | None = 0, **extra: Any) -> ObservableTrace:
    data = project if isinstance(project, bytes) else project.to_sb3()
    run = await evaluator.evaluate_traced(data, SPEC, random_seed=seed, **extra)
    assert run.result.error is None and run.result.success, run.result
    assert run.trace is not None
    return run.trace


async def difference(evaluator: Evaluator, golden: Project | bytes, variant: Project | bytes) -> TraceDifference:
    found = first_difference(await traced(evaluator, golden), await traced(evaluator, variant))
    assert found is not None
    return found


def first_frame_with(trace: ObservableTrace, target: str, field: str) -> int:
    """The first frame after the start in which ``target``'s ``field`` was recorded."""
    return next(f.frame for f in trace.frames if f.frame > 0 and field in f.targets.get(target, {}))


async def test_a_changed_say_literal_is_named_by_frame_target_and_bubble_text(evaluator: Evaluator) -> None:
    golden = cat(block("control_wait", DURATION=0.5), block("looks_say", MESSAGE="hello"))
    variant = cat(block("control_wait", DURATION=0.5), block("looks_say", MESSAGE="hullo"))
    trace = await traced(evaluator, golden)
    found = first_difference(trace, await traced(evaluator, variant))
    assert found is not None
    # Half a second at 30 frames a second: the bubble appears some 15 frames in, where the golden's trace has it.
    assert found.frame == first_frame_with(trace, "Cat", "bubble") and 14 <= found.frame <= 17
    assert (found.target, found.field, found.a, found.b) == ("Cat", "bubble", ["say", "hello"], ["say", "hullo"])
    assert "hullo" in found.describe() and f"frame {found.frame}" in found.describe()


async def test_think_is_another_bubble_than_say(evaluator: Evaluator) -> None:
    found = await difference(evaluator, cat(block("looks_say", MESSAGE="hm")), cat(block("looks_think", MESSAGE="hm")))
    assert (found.target, found.field, found.a, found.b) == ("Cat", "bubble", ["say", "hm"], ["think", "hm"])


@pytest.mark.parametrize(
    ("golden", "variant", "field", "values"),
    [
        (block("motion_movesteps", STEPS=10), block("motion_movesteps", STEPS=11), "x", (10, 11)),
        (block("motion_turnright", DEGREES=15), block("motion_turnleft", DEGREES=15), "direction", (105, 75)),
        (block("looks_switchcostumeto", COSTUME="b"), block("looks_nextcostume"), None, None),
        (block("looks_hide"), block("looks_show"), "visible", (False, True)),
        (block("looks_setsizeto", SIZE=150), block("looks_setsizeto", SIZE=50), "size", (150, 50)),
        (block("looks_seteffectto", EFFECT="GHOST", VALUE=50), block("looks_cleargraphiceffects"), "effects", None),
        (
            block("motion_setrotationstyle", STYLE="left-right"),
            block("motion_ifonedgebounce"),
            "rotation",
            ("left-right", "all around"),
        ),
    ],
    ids=["motion", "direction", "costume-equal", "hidden", "size", "ghost", "rotation-style"],
)
async def test_each_look_of_a_sprite_is_observed(
    evaluator: Evaluator, golden: Block, variant: Block, field: str | None, values: tuple[Any, Any] | None
) -> None:
    a, b = await traced(evaluator, cat(golden)), await traced(evaluator, cat(variant))
    found = first_difference(a, b)
    if field is None:  # "next costume" from a is b: the same thing seen
        assert found is None
        return
    assert found is not None and (found.frame, found.target, found.field) == (1, "Cat", field)
    if values is not None:
        assert (found.a, found.b) == values
    if field == "effects":
        assert (found.a, found.b) == ({"ghost": 50}, {})


async def test_a_changed_costume_is_observed(evaluator: Evaluator) -> None:
    found = await difference(
        evaluator, cat(block("looks_switchcostumeto", COSTUME="b")), cat(block("looks_switchcostumeto", COSTUME="a"))
    )
    assert (found.target, found.field, found.a, found.b) == ("Cat", "costume", "b", "a")


async def test_a_changed_variable_value_is_observed_by_id(evaluator: Evaluator) -> None:
    found = await difference(
        evaluator,
        cat(block("data_setvariableto", VARIABLE="score", VALUE=5)),
        cat(block("data_setvariableto", VARIABLE="score", VALUE=6)),
    )
    assert (found.target, found.field, found.a, found.b, found.variable) == (
        "Stage",
        "var:variable-Stage-score.value",
        "5",
        "6",
        "score",
    )


async def test_a_list_change_is_observed(evaluator: Evaluator) -> None:
    found = await difference(
        evaluator,
        cat(block("data_addtolist", LIST="items", ITEM="x"), block("data_addtolist", LIST="items", ITEM="y")),
        cat(
            block("data_addtolist", LIST="items", ITEM="x"), block("data_insertatlist", LIST="items", ITEM="y", INDEX=1)
        ),
    )
    assert (found.frame, found.target, found.field) == (1, "Stage", "var:list-Stage-items.value")
    assert (found.a, found.b) == (["x", "y"], ["y", "x"])


async def test_a_number_and_its_text_look_the_same(evaluator: Evaluator) -> None:
    golden = cat(block("data_setvariableto", VARIABLE="score", VALUE=block("operator_add", NUM1=4, NUM2=6)))
    variant = cat(block("data_setvariableto", VARIABLE="score", VALUE="10"))
    assert first_difference(await traced(evaluator, golden), await traced(evaluator, variant)) is None


def final_pen(trace: ObservableTrace) -> dict[str, Any]:
    pens = [frame.targets["Stage"]["pen"] for frame in trace.frames if "pen" in frame.targets.get("Stage", {})]
    assert isinstance(pens[-1], dict)
    return pens[-1]


def drawn(*before: Block) -> Project:
    return cat(*before, block("pen_penDown"), block("motion_movesteps", STEPS=50), block("pen_penUp"))


async def test_pen_lines_dots_stamps_and_clears_are_observed_without_reading_pixels(evaluator: Evaluator) -> None:
    trace = await traced(evaluator, drawn())
    assert {k: final_pen(trace)[k] for k in ("dots", "lines", "stamps", "clears")} == {
        "dots": 1,
        "lines": 1,
        "stamps": 0,
        "clears": 0,
    }
    not_drawn = cat(block("pen_penUp"), block("motion_movesteps", STEPS=50))
    found = first_difference(trace, await traced(evaluator, not_drawn))  # moved alike, drew nothing
    assert found is not None and (found.frame, found.target, found.field) == (1, "Stage", "pen")
    stamped = await difference(evaluator, cat(block("pen_stamp")), cat(block("pen_clear")))
    assert stamped.field == "pen" and isinstance(stamped.a, dict) and isinstance(stamped.b, dict)
    assert (stamped.a["stamps"], stamped.a["clears"], stamped.b["stamps"], stamped.b["clears"]) == (1, 0, 0, 1)


async def test_the_same_pen_strokes_in_another_colour_differ(evaluator: Evaluator) -> None:
    found = await difference(
        evaluator,
        drawn(block("pen_setPenColorToColor", COLOR="#ff0000")),
        drawn(block("pen_setPenColorToColor", COLOR="#0000ff")),
    )
    assert found.field == "pen" and isinstance(found.a, dict) and isinstance(found.b, dict)
    assert found.a["lines"] == found.b["lines"] == 1 and found.a["digest"] != found.b["digest"]


async def test_a_sound_started_is_observed_on_the_target_that_played_it(evaluator: Evaluator) -> None:
    played = with_sound(cat(block("sound_play", SOUND_MENU="beep")).to_sb3(), "Cat", "beep", 0.2)
    silent = with_sound(cat(block("sound_stopallsounds")).to_sb3(), "Cat", "beep", 0.2)
    found = await difference(evaluator, played, silent)
    assert (found.frame, found.target, found.field, found.a, found.b) == (1, "Cat", "sounds", ["beep"], [])


def monitored(project: Project, variable_id: str, sprite: str | None = None) -> dict[str, Any]:
    """The project's JSON with a shown monitor of the variable ``variable_id`` (of ``sprite``, or global).

    Written into the file rather than shown by a block at the green flag: a "show variable" in the first
    frames after a load is lost when the editor's flyout has not caught up with the new project yet.
    """
    data = project.to_project_json()
    owner = next(t for t in data["targets"] if (t["name"] == sprite if sprite else t["isStage"]))
    name = owner["variables"][variable_id][0]
    data["monitors"].append(
        {
            "id": variable_id,
            "mode": "default",
            "opcode": "data_variable",
            "params": {"VARIABLE": name},
            "spriteName": sprite,
            "value": 0,
            "width": 0,
            "height": 0,
            "x": 5,
            "y": 5,
            "visible": True,
            "sliderMin": 0,
            "sliderMax": 100,
            "isDiscrete": True,
        }
    )
    return data


def renamed(project: Project, variable_id: str, new_name: str, shown: bool = False) -> bytes:
    """The project with the variable ``variable_id`` renamed everywhere (its id kept), as the editor renames
    (``shown``: with a shown monitor of it, before and after)."""

    def rename(node: Any) -> Any:
        if isinstance(node, dict) and node.get("id") == variable_id and "params" in node:  # its monitor
            return {**node, "params": {"VARIABLE": new_name}}
        if isinstance(node, dict):  # the declaration: {id: [name, value]}
            return {key: [new_name, *value[1:]] if key == variable_id else rename(value) for key, value in node.items()}
        if isinstance(node, list) and variable_id in node[1:]:  # a field [name, id], an input [12, name, id]
            at = node.index(variable_id) - 1
            return [new_name if i == at else item for i, item in enumerate(node)]
        if isinstance(node, list):
            return [rename(item) for item in node]
        return node

    data = monitored(project, variable_id) if shown else project.to_project_json()
    return Sb3Archive(project.to_sb3()).with_project(rename(data))


async def test_a_renamed_hidden_variable_leaves_the_trace_equal(evaluator: Evaluator) -> None:
    project = cat(block("data_changevariableby", VARIABLE="score", VALUE=3), block("motion_movesteps", STEPS=5))
    a = await traced(evaluator, project)
    b = await traced(evaluator, renamed(project, "variable-Stage-score", "points"))
    assert a.frames[0].targets["Stage"]["var:variable-Stage-score"] == ["score", "0", False]
    assert b.frames[0].targets["Stage"]["var:variable-Stage-score"] == ["points", "0", False]
    assert first_difference(a, b) is None


async def test_a_renamed_shown_variable_differs_by_its_label(evaluator: Evaluator) -> None:
    project = cat(block("data_changevariableby", VARIABLE="score", VALUE=3))
    shown = Sb3Archive(project.to_sb3()).with_project(monitored(project, "variable-Stage-score"))
    a, b = (
        await traced(evaluator, shown),
        await traced(evaluator, renamed(project, "variable-Stage-score", "points", True)),
    )
    assert a.frames[0].targets["Stage"]["var:variable-Stage-score"] == ["score", "0", True]
    found = first_difference(a, b)
    assert found is not None and (found.frame, found.field, found.a, found.b) == (
        0,
        "var:variable-Stage-score.name",
        "score",
        "points",
    )


async def test_a_hidden_helper_variable_leaves_the_trace_equal_a_shown_one_does_not(evaluator: Evaluator) -> None:
    golden = await traced(
        evaluator, cat(block("control_repeat", TIMES=5, SUBSTACK=[block("motion_movesteps", STEPS=2)]))
    )
    # A refactoring that counts its steps in a helper variable of its own.
    helper = cat(
        block(
            "control_repeat",
            TIMES=5,
            SUBSTACK=[block("motion_movesteps", STEPS=2), block("data_changevariableby", VARIABLE="steps", VALUE=1)],
        )
    )
    helper.sprites[0].variable("steps", 0)
    assert first_difference(golden, await traced(evaluator, helper)) is None
    shown = Sb3Archive(helper.to_sb3()).with_project(monitored(helper, "variable-Cat-steps", "Cat"))
    found = first_difference(golden, await traced(evaluator, shown))
    assert found is not None and (found.frame, found.target, found.field) == (0, "Cat", "var:variable-Cat-steps")
    assert (found.a, found.b, found.variable) == (None, ["steps", "0", True], "steps")


def random_walker() -> Project:
    """Clones that go to random places and say random numbers, each deleted after a while."""
    project = cat(
        block(
            "control_repeat",
            TIMES=4,
            SUBSTACK=[block("control_create_clone_of", CLONE_OPTION="_myself_"), block("control_wait", DURATION=0.1)],
        )
    )
    project.sprites[0].script(
        block("control_start_as_clone"),
        block(
            "motion_gotoxy",
            X=block("operator_random", FROM=-200, TO=200),
            Y=block("operator_random", FROM=-150, TO=150),
        ),
        block("looks_say", MESSAGE=block("operator_random", FROM=1, TO=1000000)),
        block("data_changevariableby", VARIABLE="score", VALUE=1),
        block("control_wait", DURATION=0.3),
        block("control_delete_this_clone"),
    )
    return project


async def test_the_same_seed_gives_the_same_trace_and_another_seed_other_random_numbers(evaluator: Evaluator) -> None:
    project = random_walker()
    first, again = await traced(evaluator, project, seed=7), await traced(evaluator, project, seed=7)
    assert first == again and first_difference(first, again) is None
    assert not first.truncated and first.steps >= 44  # the whole 1.5 s, frame by frame
    keys = {key for frame in first.frames for key in frame.targets}
    assert {"Stage", "Cat", "Cat#1", "Cat#2", "Cat#3", "Cat#4"} <= keys  # clones by creation order
    assert {"Cat#1", "Cat#4"} <= {key for frame in first.frames for key in frame.removed}
    other = await traced(evaluator, project, seed=8)
    found = first_difference(first, other)
    assert found is not None and found.target == "Cat#1" and found.field in ("x", "y")


async def test_the_size_cap_flags_truncation_and_keeps_the_verdict(evaluator: Evaluator) -> None:
    project = cat(block("control_forever", SUBSTACK=[block("motion_turnright", DEGREES=7)]))
    whole = await traced(evaluator, project)
    cut = await traced(evaluator, project, max_chars=1000)
    assert not whole.truncated and whole.chars > 1000
    assert cut.truncated and cut.truncated_at is not None and cut.chars <= 1000
    assert cut.frames == whole.frames[: len(cut.frames)] and cut.truncated_at == whole.frames[len(cut.frames)].frame
    assert first_difference(whole, cut) is None  # nothing differs in what both recorded


async def test_a_failing_script_still_gives_its_trace(evaluator: Evaluator) -> None:
    failing = SPEC.model_copy(update={"script_source": RUN_A_WHILE.replace("return", "throw new Error('late');")})
    run: TracedEvaluation = await evaluator.evaluate_traced(cat(block("motion_movesteps", STEPS=10)).to_sb3(), failing)
    assert run.result.error is not None and run.result.error.kind == "script_error"
    assert run.trace is not None and run.trace.steps >= 44
    assert run.trace.frames[1].targets["Cat"] == {"x": 10}


async def test_a_bad_cap_is_refused_before_any_page_is_used(evaluator: Evaluator) -> None:
    with pytest.raises(ValueError, match="max_chars must be from 1000"):
        await evaluator.evaluate_traced(cat().to_sb3(), SPEC, max_chars=10)


LEFT_BEHIND = """
module.exports = async (vm) => {
  const runtime = vm.runtime;
  const bank = runtime.targets.map((t) => t.sprite && t.sprite.soundBank).find(Boolean);
  const hooked = {
    step: Object.prototype.hasOwnProperty.call(runtime, '_step'),
    pen: ['penLine', 'penPoint', 'penStamp', 'penClear']
      .some((name) => Object.prototype.hasOwnProperty.call(vm.renderer, name)),
    sound: String(Object.getPrototypeOf(bank).playSound).includes('before.apply'),
    question: runtime.listeners('QUESTION').length,
  };
  return {details: [{name: 'nothing of the trace is left', passed: true, meta: hooked}]};
};
"""


async def test_a_traced_page_is_left_as_it_was_and_reused(session: BrowserSession) -> None:
    # No pen blocks: a page that loaded an extension is never reused (the hooks on the renderer are there anyway).
    moves = cat(
        block("sound_play", SOUND_MENU="beep"), block("motion_movesteps", STEPS=50), block("looks_say", MESSAGE="hi")
    )
    project = with_sound(moves.to_sb3(), "Cat", "beep", 0.2)
    async with EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        plain = await evaluator.evaluate(project, SPEC.model_copy(update={"script_source": LEFT_BEHIND}))
        listeners = plain.tests[0].meta["question"]  # type: ignore[index]
        run = await evaluator.evaluate_traced(project, SPEC)
        assert run.trace is not None and run.record_s is not None and run.record_s > 0
        assert any(frame.targets.get("Cat", {}).get("sounds") == ["beep"] for frame in run.trace.frames)
        after = await evaluator.evaluate(project, SPEC.model_copy(update={"script_source": LEFT_BEHIND}))
        assert after.tests[0].meta == {"step": False, "pen": False, "sound": False, "question": listeners}
        assert pool.opened == 1 and pool.reused == 2 and not pool.discarded  # recycled clean after the trace
        again = await evaluator.evaluate_traced(project, SPEC)  # in the page the first trace was taken from
        assert again.trace is not None and again.trace.frames == run.trace.frames
