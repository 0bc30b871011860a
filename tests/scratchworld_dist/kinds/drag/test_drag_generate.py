"""Drag tasks generated from projects: every connection kind is found, each cut is exact (re-making
the expected connection gives the original scripts back), palette variants delete their block, and
odd projects become one-line problems, never exceptions."""

from __future__ import annotations

import copy
import json
import random
from collections import Counter
from pathlib import Path
from typing import Any

import pytest

from scratchworld_dist.kinds.drag.items import CanvasSource, DragView, FlyoutSource, load_drag_suite, write_drag_suite
from scratchworld_dist.kinds.drag.items._checks import OUR_FIELDS, block_problems
from scratchworld_dist.kinds.drag.items._generate import DragCandidate, drag_candidates, select_candidates
from scratchworld_dist.kinds.drag.items._project import ProjectIndex, palette_category_of
from scratchworld_dist.sb3 import Project, block, check_project, circle_costume, variable
from scratchworld_dist.suites._task import task_id_problem
from tests.conftest import REPO

TASKS = REPO / "tasks"
FIRST_SCRIPT = {"event_whenflagclicked", "motion_movesteps", "control_forever", "control_if", "motion_turnright"}
ALL_COMBOS = {(k, s) for k in ("next", "parent", "substack_1", "substack_2", "input") for s in ("canvas", "flyout")}


def _fixture() -> bytes:
    """Every connection kind, each once with a single palette block (so a flyout variant exists)."""
    project = Project()
    project.stage.variable("score", 0)
    project.stage.script(block("event_whenflagclicked"), block("control_wait", DURATION=1), block("looks_nextbackdrop"))
    cat = project.sprite("Cat", costume=circle_costume("c", 10, "#f00"))
    cat.script(
        block("event_whenflagclicked"),
        block("motion_movesteps", STEPS=10),
        block(
            "control_forever",
            SUBSTACK=[
                block(
                    "control_if",
                    CONDITION=block("sensing_touchingobject", TOUCHINGOBJECTMENU="_mouse_"),
                    SUBSTACK=[block("motion_turnright", DEGREES=15)],
                )
            ],
        ),
    )
    cat.script(
        block("event_whenkeypressed", KEY_OPTION="space"),
        block(
            "control_if_else",
            CONDITION=block("operator_gt", OPERAND1=block("motion_xposition"), OPERAND2=50),
            SUBSTACK=[block("looks_say", MESSAGE=variable("score"))],
            SUBSTACK2=[block("looks_say", MESSAGE="left")],
        ),
    )
    return project.to_sb3()


SB3 = _fixture()
ORIGINAL = check_project(SB3)
CANDIDATES, PROBLEMS = drag_candidates(SB3, project_name="fixture")


def _blocks(project: dict[str, Any], sprite: str | None) -> dict[str, Any]:
    target = next(t for t in project["targets"] if (t["isStage"] if sprite is None else t["name"] == sprite))
    return target["blocks"]


def _reattach(original: dict[str, Any], candidate: DragCandidate) -> bool:
    """Make the candidate's expected connection in its project, as the editor would save it, and
    compare with the original's blocks (positions aside) and its other targets (exactly)."""
    changed = check_project(candidate.project)
    before, blocks = _blocks(original, candidate.sprite), copy.deepcopy(_blocks(changed, candidate.sprite))
    if isinstance(candidate.source, CanvasSource):
        source_id, tail = candidate.source.block_id, candidate.source.tail_block_id
    else:  # the palette's new block: as the original had it, shadows included
        source_id = tail = candidate.detached_block_id
        todo = [source_id]
        while todo:
            current = todo.pop()
            blocks[current] = copy.deepcopy(before[current])
            todo += [r for entry in before[current]["inputs"].values() for r in entry[1:3] if isinstance(r, str)]
    ref_id, connection = candidate.reference_block_id, candidate.connection
    reference, source = blocks[ref_id], blocks[source_id]
    attached = source
    if connection.kind == "parent":
        blocks[tail]["next"], reference["parent"], attached = ref_id, tail, reference
    elif connection.kind == "next":
        reference["next"], source["parent"] = source_id, ref_id
    else:
        entry = reference["inputs"].get(connection.input_name or _substack(connection.kind))
        shadow = entry[1] if connection.kind == "input" and entry and entry[0] == 1 else None
        if source["opcode"] == "data_variable" and not source["inputs"]:  # saved compactly, as Scratch does
            name, variable_id = source["fields"]["VARIABLE"]
            assert name == connection.variable_name
            del blocks[source_id]
            source_id = [12, name, variable_id]
        value = [3, source_id, shadow] if shadow is not None else [2, source_id]
        reference["inputs"][connection.input_name or _substack(connection.kind)] = value
        if isinstance(source_id, str):
            source["parent"] = ref_id
    attached["topLevel"] = False

    def bare(found: dict[str, Any]) -> dict[str, Any]:
        return {
            i: {k: bool(v) if k == "topLevel" else v for k, v in b.items() if k not in ("x", "y")}
            for i, b in found.items()
        }

    def others(project: dict[str, Any]) -> list[Any]:
        return [t for t in project["targets"] if t["blocks"] is not _blocks(project, candidate.sprite)]

    return bare(blocks) == bare(before) and others(original) == others(changed)


def _substack(kind: str) -> str:
    return {"substack_1": "SUBSTACK", "substack_2": "SUBSTACK2"}[kind]


def _task_projects() -> list[tuple[str, bytes]]:
    paths = sorted(TASKS.glob("*/*/*.sb3"))
    return [(str(p.relative_to(TASKS).with_suffix("")), p.read_bytes()) for p in paths]


def test_every_connection_kind_and_source_kind_is_found() -> None:
    assert PROBLEMS == []
    assert {(c.connection.kind, c.source.kind) for c in CANDIDATES} == ALL_COMBOS
    assert {c.type for c in CANDIDATES if c.connection.kind in ("next", "parent")} == {"T1"}
    assert {c.type for c in CANDIDATES if c.connection.kind not in ("next", "parent")} == {"T2"}
    # Stage: 2 next, 2 parent; Cat: 3 next, 3 parent, 3 + 1 substack, 4 input (touching, >, x position, score)
    assert Counter(c.connection.kind for c in CANDIDATES if c.source.kind == "canvas") == {
        "next": 5,
        "parent": 5,
        "substack_1": 3,
        "substack_2": 1,
        "input": 4,
    }


def test_each_cut_detaches_exactly_the_source() -> None:
    for candidate in (c for c in CANDIDATES if isinstance(c.source, CanvasSource)):
        changed = check_project(candidate.project)
        blocks, before = _blocks(changed, candidate.sprite), _blocks(ORIGINAL, candidate.sprite)
        reference, source = blocks[candidate.reference_block_id], blocks[candidate.source.block_id]
        assert source["topLevel"] and source["parent"] is None, candidate.id
        assert isinstance(source["x"], int) and isinstance(source["y"], int)
        kind = candidate.connection.kind
        if kind == "next":
            assert reference["next"] is None
        elif kind == "parent":
            assert blocks[candidate.source.tail_block_id]["next"] is None
            assert reference["topLevel"] and reference["parent"] is None
        elif kind.startswith("substack"):
            assert _substack(kind) not in reference["inputs"]
        else:
            name = candidate.connection.input_name
            old = before[candidate.reference_block_id]["inputs"][name]
            # the shadow the reporter hid is back; a boolean slot without one is empty
            assert reference["inputs"].get(name) == ([1, old[2]] if old[0] == 3 else None), candidate.id
        index = ProjectIndex.from_json(changed)
        assert (
            block_problems(
                index, candidate.source, candidate.reference_block_id, candidate.reference_opcode, OUR_FIELDS
            )
            == []
        ), candidate.id


def test_reattaching_gives_back_the_original() -> None:
    for candidate in CANDIDATES:
        assert _reattach(ORIGINAL, candidate), candidate.id
    # and the check can fail: a connection made to the wrong block is not the original
    wrong = next(c for c in CANDIDATES if c.connection.kind == "next" and c.source.kind == "canvas")
    other = next(i for i, b in _blocks(ORIGINAL, wrong.sprite).items() if i != wrong.reference_block_id and b["next"])
    assert not _reattach(ORIGINAL, wrong.model_copy(update={"reference_block_id": other}))


def test_a_variable_reporter_stored_compactly_becomes_a_block_with_a_stable_id() -> None:
    candidate = next(c for c in CANDIDATES if c.connection.variable_name is not None)
    assert candidate.connection.variable_name == "score" and candidate.connection.input_name == "MESSAGE"
    assert isinstance(candidate.source, CanvasSource) and candidate.source.opcode == "data_variable"
    assert candidate.detached_block_id is None
    source = _blocks(check_project(candidate.project), "Cat")[candidate.source.block_id]
    # a compact entry would get a new random id in the VM on load; the full form keeps ours
    assert isinstance(source, dict) and source["fields"]["VARIABLE"][0] == "score"
    assert candidate.instruction == "Drag the “score” variable and drop it into the slot of “say []”."


def test_palette_variants_delete_the_block_and_its_shadows() -> None:
    flyout = [c for c in CANDIDATES if isinstance(c.source, FlyoutSource)]
    assert {c.source.opcode for c in flyout} == {
        "looks_nextbackdrop",
        "event_whenflagclicked",
        "event_whenkeypressed",
        "motion_turnright",
        "looks_say",
        "sensing_touchingobject",
        "motion_xposition",
    }
    for candidate in flyout:
        before = _blocks(ORIGINAL, candidate.sprite)
        after = _blocks(check_project(candidate.project), candidate.sprite)
        gone = set(before) - set(after)
        shadows = {
            r for e in before[candidate.detached_block_id]["inputs"].values() for r in e[1:3] if isinstance(r, str)
        }
        assert gone == {candidate.detached_block_id, *shadows}, candidate.id
        assert set(after) <= set(before)
        assert candidate.category == palette_category_of(candidate.source.opcode)
        assert candidate.id.endswith("-flyout") and candidate.id.removesuffix("-flyout") in {c.id for c in CANDIDATES}
        assert "palette" in candidate.instruction
    turn = next(c for c in flyout if c.source.opcode == "motion_turnright")
    assert turn.instruction == (
        "Drag a new “turn right (15) degrees” block from the Motion palette and put it inside the mouth of "
        "“if <touching [mouse-pointer]?> then”."
    )
    say = next(c for c in flyout if c.connection.kind == "substack_2")
    assert say.instruction.endswith("into the second (“else”) branch of “if <(x position) > (50)> then else”.")


def test_the_stage_palette_has_no_motion_blocks() -> None:
    project = Project()
    project.stage.script(block("event_whenflagclicked"), block("motion_movesteps", STEPS=5))
    found, problems = drag_candidates(project.to_sb3(), project_name="stage")
    assert problems == []
    assert {(c.connection.kind, c.source.kind, c.sprite) for c in found} == {
        ("next", "canvas", None),
        ("parent", "canvas", None),
        ("parent", "flyout", None),  # when green flag clicked is in the Stage's palette
    }


def test_ids_are_plain_unique_and_stable() -> None:
    ids = [c.id for c in CANDIDATES]
    assert len(set(ids)) == len(ids)
    assert all(task_id_problem(i) is None and i.startswith("fixture-") for i in ids)
    again, _ = drag_candidates(SB3, project_name="fixture")
    assert [(c.id, c.project) for c in again] == [(c.id, c.project) for c in CANDIDATES]
    renamed, _ = drag_candidates(SB3, project_name="../we ird\nname")
    assert all(task_id_problem(c.id) is None for c in renamed)
    assert not {c.id for c in renamed} & set(ids)


def test_task_projects_give_over_a_hundred_exact_candidates() -> None:
    total: list[DragCandidate] = []
    for name, data in _task_projects():
        found, problems = drag_candidates(data, project_name=name)
        assert problems == [], name
        original = check_project(data)
        for candidate in found:
            assert _reattach(original, candidate), candidate.id
            if isinstance(candidate.source, CanvasSource):
                index = ProjectIndex.from_json(check_project(candidate.project))
                assert not block_problems(
                    index, candidate.source, candidate.reference_block_id, candidate.reference_opcode, OUR_FIELDS
                )
        total += found
    assert len(total) > 100
    assert len({c.id for c in total}) == len(total)
    assert {(c.connection.kind, c.source.kind) for c in total} == ALL_COMBOS


def test_selection_is_balanced_and_deterministic() -> None:
    everything, _ = drag_candidates(SB3, project_name="other")
    pool = CANDIDATES + everything
    four = select_candidates(pool, limit_per_project=4, seed=7)
    assert Counter(c.project_name for c in four) == {"fixture": 4, "other": 4}
    for name in ("fixture", "other"):
        picked = [c for c in four if c.project_name == name]
        assert {c.type for c in picked} == {"T1", "T2"} and {c.source.kind for c in picked} == {"canvas", "flyout"}
    assert select_candidates(list(reversed(pool)), limit_per_project=4, seed=7) == four
    ten = select_candidates(CANDIDATES, limit_per_project=10, seed=3)
    assert {(c.connection.kind, c.source.kind) for c in ten} == ALL_COMBOS
    # distinct connections but for the fixture's only substack_2 one, which both its variants need
    bases = Counter(c.id.removesuffix("-flyout") for c in ten)
    assert [c.connection.kind for c in ten if bases[c.id.removesuffix("-flyout")] > 1] == ["substack_2"] * 2
    assert select_candidates(CANDIDATES, limit_per_project=None, seed=0) == sorted(CANDIDATES, key=lambda c: c.id)
    assert select_candidates(CANDIDATES, limit_per_project=0, seed=0) == []
    with pytest.raises(ValueError, match="limit_per_project"):
        select_candidates(CANDIDATES, limit_per_project=-1, seed=0)


def test_candidates_become_a_suite_that_loads(tmp_path: Path) -> None:
    tasks = []
    for candidate in select_candidates(CANDIDATES, limit_per_project=10, seed=1):
        path = tmp_path / "projects" / f"{candidate.id}.sb3"
        path.parent.mkdir(exist_ok=True)
        path.write_bytes(candidate.project)
        view = DragView(sprite=candidate.sprite, category=candidate.category, scroll_x=0, scroll_y=0, scale=0.675)
        tasks.append(candidate.task(path, view))
    suite = load_drag_suite(write_drag_suite(tasks, tmp_path / "suite", "generated"))
    assert suite.problems == () and len(suite.tasks) == 10


def _hostile(edit: Any) -> tuple[list[DragCandidate], list[str]]:
    project = copy.deepcopy(ORIGINAL)
    edit(project)
    found, problems = drag_candidates(json.dumps(project).encode(), project_name="odd")
    for problem in problems:
        assert problem.project == "odd" and "\n" not in problem.message
    return found, [p.message for p in problems]


def _cat(project: dict[str, Any]) -> dict[str, Any]:
    return next(t for t in project["targets"] if t.get("name") == "Cat")


def _first_block(project: dict[str, Any], opcode: str) -> dict[str, Any]:
    return next(b for b in _cat(project)["blocks"].values() if b["opcode"] == opcode)


def test_odd_projects_are_problems_not_crashes() -> None:
    found, problems = drag_candidates(b"not a project", project_name="junk")
    assert found == [] and len(problems) == 1 and "not a usable project" in problems[0].message
    # a wrong parent pointer skips that script only; the other scripts still give tasks
    found, problems = _hostile(lambda p: _first_block(p, "motion_movesteps").update(parent="nowhere"))
    assert len(problems) == 1 and "names parent 'nowhere'" in problems[0]
    first = {i for i, b in _cat(ORIGINAL)["blocks"].items() if b["opcode"] in FIRST_SCRIPT}
    assert any(c.sprite == "Cat" for c in found)
    assert not any(c.reference_block_id in first or c.detached_block_id in first for c in found if c.sprite == "Cat")
    # bare JSON in, bare JSON out
    assert all(c.project.lstrip().startswith(b"{") for c in found)

    def cycle(project: dict[str, Any]) -> None:
        blocks = _cat(project)["blocks"]
        move = next(i for i, b in blocks.items() if b["opcode"] == "motion_movesteps")
        forever = next(b for b in blocks.values() if b["opcode"] == "control_forever")
        forever["next"] = move

    assert any("reached twice" in m or "names parent" in m for m in _hostile(cycle)[1])
    duplicate = _hostile(lambda p: p["targets"].append(copy.deepcopy(_cat(p))))
    assert sum("not unique by name" in m for m in duplicate[1]) == 2
    assert {c.sprite for c in duplicate[0]} == {None}
    weird = _hostile(lambda p: p["targets"].extend([7, {"name": "X", "blocks": []}]))
    assert len(weird[1]) == 2 and len(weird[0]) == len(CANDIDATES)
    broken = _hostile(lambda p: _first_block(p, "control_if").update(inputs={"CONDITION": "x"}))
    assert len(broken[1]) == 1 and "not a list" in broken[1][0]
    nameless = _hostile(lambda p: _first_block(p, "motion_movesteps").update(opcode=5))
    assert len(nameless[1]) == 1 and "no opcode" in nameless[1][0]


def test_comments_on_a_deleted_block_are_unpinned() -> None:
    project = copy.deepcopy(ORIGINAL)
    turn = next(i for i, b in _cat(project)["blocks"].items() if b["opcode"] == "motion_turnright")
    _cat(project)["comments"] = {"c1": {"blockId": turn, "x": 0, "y": 0, "text": "turn!", "minimized": False}}
    found, _ = drag_candidates(json.dumps(project).encode(), project_name="notes")
    deleted = next(c for c in found if c.detached_block_id == turn and c.source.kind == "flyout")
    assert _cat(check_project(deleted.project))["comments"]["c1"]["blockId"] is None
    moved = next(c for c in found if c.detached_block_id == turn and c.source.kind == "canvas")
    assert _cat(check_project(moved.project))["comments"]["c1"]["blockId"] == turn


JUNK = [None, 5, -1e308, "zz", "", [], {}, [1], [2], [12, "a"], [3, None, None], {"a": 1}, True, [[1]], "nowhere"]


def test_random_damage_never_raises() -> None:
    rng = random.Random(5)
    ids = {name: list(_blocks(ORIGINAL, name)) for name in (None, "Cat")}
    for _ in range(300):
        project = copy.deepcopy(ORIGINAL)
        sprite = rng.choice([None, "Cat"])
        blocks = _blocks(project, sprite)
        victim = blocks[rng.choice(ids[sprite])]
        key = rng.choice(["next", "parent", "inputs", "fields", "opcode", "shadow", "topLevel", "mutation", "x"])
        if key == "inputs" and victim["inputs"] and rng.random() < 0.7:
            victim["inputs"][rng.choice(list(victim["inputs"]))] = rng.choice([*JUNK, [1, rng.choice(ids[sprite])]])
        else:
            victim[key] = rng.choice([*JUNK, rng.choice(ids[sprite])])
        found, problems = drag_candidates(json.dumps(project).encode(), project_name="damaged")
        assert all("\n" not in p.message for p in problems)
        for candidate in found:  # what is still offered is still exact
            assert _reattach(project, candidate), (key, candidate.id)


def test_custom_blocks_keep_their_definition_whole() -> None:
    """A definition's prototype and its argument shadows are never cut; a call's inputs are ordinary."""
    project = Project()
    project.sprite("Cat", costume=circle_costume("c", 10, "#f00")).script(block("event_whenflagclicked"))
    data = project.to_project_json()
    mutation = {"tagName": "mutation", "children": [], "proccode": "jump %s high", "argumentids": '["a1"]'}

    def put(block_id: str, opcode: str, parent: str | None, **extra: Any) -> None:
        record = {"opcode": opcode, "next": None, "parent": parent, "inputs": {}, "fields": {}, "shadow": False}
        data["targets"][1]["blocks"][block_id] = record | {"topLevel": parent is None} | extra

    put("def", "procedures_definition", None, next="chg", inputs={"custom_block": [1, "proto"]}, x=0, y=300)
    put("proto", "procedures_prototype", "def", inputs={"a1": [1, "arg"]}, mutation=mutation, shadow=True)
    put("arg", "argument_reporter_string_number", "proto", fields={"VALUE": ["h", None]}, shadow=True)
    put("chg", "motion_changeyby", "def", inputs={"DY": [3, "use", [4, "10"]]})
    put("use", "argument_reporter_string_number", "chg", fields={"VALUE": ["h", None]})
    put("call", "procedures_call", "Cat-1", inputs={"a1": [3, "xp", [10, "5"]]}, mutation=mutation)
    put("xp", "motion_xposition", "call")
    data["targets"][1]["blocks"]["Cat-1"]["next"] = "call"
    found, problems = drag_candidates(json.dumps(data).encode(), project_name="custom")
    assert problems == []
    assert {(c.connection.kind, c.reference_block_id, c.detached_block_id, c.source.kind) for c in found} == {
        ("next", "Cat-1", "call", "canvas"),
        ("parent", "call", "Cat-1", "canvas"),
        ("parent", "call", "Cat-1", "flyout"),
        ("input", "call", "xp", "canvas"),
        ("input", "call", "xp", "flyout"),
        ("next", "def", "chg", "canvas"),
        ("parent", "chg", "def", "canvas"),
        ("input", "chg", "use", "canvas"),  # an argument reporter has no palette block of its own
    }
    assert all(_reattach(data, c) for c in found)
    call_input = next(c for c in found if c.detached_block_id == "xp" and c.source.kind == "canvas")
    assert call_input.instruction == "Drag the “x position” block and drop it into the slot of “jump (5) high”."
