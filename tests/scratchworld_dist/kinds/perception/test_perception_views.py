"""Perturbed views as changes to project.json, and the balanced selection of items (no browser)."""

from __future__ import annotations

import random
from collections import Counter
from typing import Any

from scratchworld_dist.kinds.perception.items import BlockReference, ConnectionFact, ExistenceFact, FieldFact
from scratchworld_dist.kinds.perception.items._candidates import Candidate, candidates
from scratchworld_dist.kinds.perception.items._derive import Derived
from scratchworld_dist.kinds.perception.items._facts import Point
from scratchworld_dist.kinds.perception.items._perturb import (
    CUT,
    SIDEWAYS,
    ZOOM_OUT,
    bumped,
    cut_view,
    perturbations,
    zoom_view,
)
from scratchworld_dist.kinds.perception.items._select import select
from scratchworld_dist.sb3 import Project, block, circle_costume
from tests.support.perception_facts import block as facts_block
from tests.support.perception_facts import changed, slot, view
from workers.contract import DragView


def _blocks() -> dict[str, Any]:
    project = Project()
    cat = project.sprite("Cat", costume=circle_costume("c", 10, "#f00"))
    cat.script(
        block("event_whenflagclicked"),
        block("looks_say", MESSAGE="Hi"),
        block(
            "control_if",
            CONDITION=block("sensing_touchingobject", TOUCHINGOBJECTMENU="_edge_"),
            SUBSTACK=[block("motion_turnright", DEGREES=15)],
        ),
    )
    cat.script(block("event_whenkeypressed", KEY_OPTION="space"), block("looks_hide"), x=300, y=40)
    return project.to_project_json()["targets"][1]["blocks"]


BLOCKS = _blocks()
# The same scripts as the editor would lay them out at scale 0.675 (page px), all in view.
FACTS = view(
    facts_block("Cat-1", "event_whenflagclicked", (400, 120, 110, 50), next="Cat-2", xy=(40, 40)),
    facts_block("Cat-2", "looks_say", (400, 163, 110, 38), parent="Cat-1", next="Cat-3", xy=(40, 104)),
    facts_block(
        "Cat-3", "control_if", (400, 196, 190, 90), parent="Cat-2", xy=(40, 152),
        inputs=[slot("CONDITION", "boolean", "Cat-4"), slot("SUBSTACK", "statement", "Cat-6")],
    ),
    facts_block("Cat-4", "sensing_touchingobject", (420, 200, 120, 30), parent="Cat-3", input="CONDITION",
                reporter=True, xy=(70, 156)),
    facts_block("Cat-6", "motion_turnright", (416, 236, 140, 38), parent="Cat-3", input="SUBSTACK", xy=(56, 216)),
    facts_block("Cat-7", "event_whenkeypressed", (575, 120, 150, 50), next="Cat-8", xy=(300, 40)),
    facts_block("Cat-8", "looks_hide", (575, 163, 80, 38), parent="Cat-7", xy=(300, 104)),
)  # fmt: skip


def _subtree(blocks: dict[str, Any], top: str) -> set[str]:
    found, todo = set(), [top]
    while todo:
        current = todo.pop()
        found.add(current)
        todo += [b for b, v in blocks.items() if v.get("parent") == current and b not in found]
    return found


def _change(kind: str) -> Any:
    found = [p for p in perturbations(BLOCKS, FACTS, random.Random(3)) if p.kind == kind]
    assert len(found) == 1, kind
    return found[0]


def test_a_pulled_off_stack_is_cut_loose_beside_its_old_place_and_drawn_last() -> None:
    change = _change("pull_off")
    assert len(change.attempts) == len(SIDEWAYS)
    first = change.attempts[0]
    loose = [key for key, b in first.items() if b.get("topLevel") and key not in ("Cat-1", "Cat-7")]
    assert len(loose) == 1
    moved = first[loose[0]]
    upper = first[moved_parent] if (moved_parent := BLOCKS[loose[0]]["parent"]) else None
    assert upper is not None and upper["next"] is None and moved["parent"] is None
    xy = FACTS.block(loose[0]).xy  # type: ignore[union-attr]
    assert (moved["x"], moved["y"]) == (round(xy.x + SIDEWAYS[0]), round(xy.y))
    stack = _subtree(first, loose[0])
    assert set(list(first)[-len(stack) :]) == stack  # drawn over the rest
    assert "pulled off" in change.change
    assert BLOCKS["Cat-1"]["next"] == "Cat-2"  # the original is not touched


def test_a_reporter_beside_its_slot_leaves_the_slot_empty() -> None:
    change = _change("beside_slot")
    first = change.attempts[0]
    assert "CONDITION" not in first["Cat-3"]["inputs"]  # a pointed slot has no shadow to show again
    assert first["Cat-4"]["topLevel"] and first["Cat-4"]["parent"] is None
    assert (first["Cat-4"]["x"], first["Cat-4"]["y"]) == (70 + 56, 156)
    assert list(first)[-2:] == ["Cat-4", "Cat-5"]  # the reporter and its menu are drawn over the if


def test_a_covering_script_moves_over_the_other_and_is_drawn_last() -> None:
    change = _change("cover")
    for attempt in change.attempts:
        movers = [
            k for k in ("Cat-1", "Cat-7") if (attempt[k]["x"], attempt[k]["y"]) != (BLOCKS[k]["x"], BLOCKS[k]["y"])
        ]
        assert len(movers) == 1
        assert list(attempt)[-1] in {"Cat-8", "Cat-6", "Cat-5"}  # the mover's blocks come last
    assert "laid over" in change.change


def test_a_one_script_target_is_split_over_itself() -> None:
    single = {k: v for k, v in BLOCKS.items() if k not in ("Cat-7", "Cat-8")}
    facts = view(*[b for b in FACTS.blocks if b.id not in ("Cat-7", "Cat-8")])
    change = next(p for p in perturbations(single, facts, random.Random(0)) if p.kind == "cover")
    first = change.attempts[0]
    assert first["Cat-1"]["next"] is None and first["Cat-2"]["topLevel"]  # cut in the middle of its 3-block stack
    assert "lower part laid over its upper part" in change.change


def test_bumped_scripts_are_those_not_where_the_project_puts_them() -> None:
    assert bumped(BLOCKS, FACTS) == []
    shifted = view(*[changed(b, xy=b.xy.model_copy(update={"x": 320})) if b.id == "Cat-7" else b for b in FACTS.blocks])
    assert bumped(BLOCKS, shifted) == ["Cat-7"]


def test_the_cut_view_puts_the_workspace_edge_through_the_widest_script() -> None:
    plain = DragView(sprite="Cat", scroll_x=-100, scroll_y=-50, scale=0.675)
    left, width = 400, 190  # the first script's extent in page px
    cut = cut_view(plain, FACTS)
    assert cut is not None
    moved_px = (cut.scroll_x - plain.scroll_x) * FACTS.scale  # the content moves left by this
    assert abs(FACTS.area.right + moved_px - left - CUT * width) < 0.01
    narrow = facts_block("x", "looks_show", (600, 300, 50, 38))
    assert cut_view(plain, view(narrow)) is None  # 38% of it is too little to cut off


def test_the_zoomed_out_view_keeps_the_scripts_in_the_middle() -> None:
    plain = DragView(sprite="Cat", scroll_x=-100, scroll_y=-50, scale=0.675)
    facts = FACTS.model_copy(update={"origin": Point(x=0, y=93)})
    zoomed = zoom_view(plain, facts)
    assert zoomed is not None and zoomed.scale == ZOOM_OUT
    middle = (400 + 325 / 2, 120 + 166 / 2)  # the scripts' extent's middle, page px, at the plain view

    def page(x: float, y: float, at: DragView) -> tuple[float, float]:
        units = (plain.scroll_x + x / plain.scale, plain.scroll_y + (y - 93) / plain.scale)
        return (units[0] - at.scroll_x) * at.scale, 93 + (units[1] - at.scroll_y) * at.scale

    centre = page(*middle, zoomed)
    area = facts.area
    assert abs(centre[0] - (area.x + area.width / 2)) < 0.01 and abs(centre[1] - (area.y + area.height / 2)) < 0.01
    assert zoom_view(plain, FACTS) is None  # without the SVG's corner there is nothing to zoom around


# ---------- selection ----------


def _candidate(n: int, kind: str, answer: str) -> Candidate:
    ref = BlockReference(block=f"b{n}", name="move steps")
    fact = {
        "connection": ConnectionFact(relation="above", subject=ref),
        "existence": ExistenceFact(name=f"kind {n}", opcodes=("motion_movesteps",)),
        "field": FieldFact(subject=ref, name="STEPS", asked=None if answer == "value" else "1"),
    }[kind]
    derived = Derived("7", "exact_match_numeric", "number") if answer == "value" else Derived(answer, f"{kind}_tag")
    return Candidate(fact=fact, question=f"question {n} {kind} {answer}?", derived=derived)  # type: ignore[arg-type]


def _pools(seed: int) -> dict[str, list[Candidate]]:
    rng = random.Random(seed)
    shapes = [("connection", "YES"), ("connection", "NO"), ("existence", "YES"), ("existence", "NO"),
              ("field", "YES"), ("field", "NO"), ("field", "value")]  # fmt: skip
    return {f"view{v}": [_candidate(n, *rng.choice(shapes)) for n in range(rng.randint(3, 30))] for v in range(12)}


def test_selection_is_balanced_capped_and_repeatable() -> None:
    pools = _pools(1)
    chosen = select(pools, per_view=6, seed=0)
    assert chosen == select(pools, per_view=6, seed=0)
    assert chosen != select(pools, per_view=6, seed=1)
    assert all(1 <= len(items) <= 6 for items in chosen.values())
    counts = Counter((c.kind, c.answer_class) for items in chosen.values() for c in items)
    for kind in ("connection", "existence", "field"):
        assert counts[(kind, "YES")] == counts[(kind, "NO")] > 0
    assert sum(counts.values()) >= 40
    for view_id, items in chosen.items():
        assert all(c in pools[view_id] for c in items)


def test_candidates_of_one_view_are_settled_and_worded() -> None:
    found = candidates(FACTS, random.Random(0))
    assert {c.kind for c in found} == {"connection", "existence"}  # these facts show no values
    assert len({c.question for c in found}) == len(found)
    tags = Counter(c.derived.tag for c in found)
    assert tags["connection_yes"] and tags["connection_no_easy"] and tags["existence_no_absent"]


def test_a_target_whose_only_top_level_block_is_a_shadow_has_no_scripts_to_show() -> None:
    from scratchworld_dist.kinds.perception.items._make import _has_scripts, _tops

    shadow = {"opcode": "looks_backdrops", "parent": None, "shadow": True, "topLevel": True, "x": 1, "y": 2}
    assert _tops({**BLOCKS, "menu": shadow}) == ["Cat-1", "Cat-7"]
    assert not _has_scripts({"blocks": {"menu": shadow}})
