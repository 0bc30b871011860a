"""Perception items generated from projects in a real editor, written as a suite, re-derived from the saved
projects; a flipped label is caught; the shipped suite loads and meets its composition target."""

from __future__ import annotations

import json
import re
import shutil
from collections import Counter
from collections.abc import AsyncIterator
from pathlib import Path

import pytest

from scratchworld_dist.kinds.perception.items import load_perception_suite
from scratchworld_dist.suites._task import task_id_problem
from tests.conftest import REPO, SUITE_DIR
from tests.support.cli_runner import invoke
from workers.editor import BrowserSession, EditorPool

SHIPPED = REPO / "perception-items"
PROJECT = SUITE_DIR / "extend" / "quiz_score" / "golden.sb3"


@pytest.fixture(scope="module")
async def pool(session: BrowserSession) -> AsyncIterator[EditorPool]:
    async with EditorPool(session, spare=0) as editors:
        yield editors


@pytest.fixture(scope="module")
async def made(pool: EditorPool, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, int]:
    """A suite made from one of our projects (all six kinds of view), and how many items it holds."""
    from scratchworld_dist.kinds.perception.items._make import make_perception_suite

    out = tmp_path_factory.mktemp("perception") / "suite"
    done = await make_perception_suite([PROJECT], out, name="one", per_view=6, seed=1, pool=pool)
    return out, done.items


def flipped_copy(suite: Path, dest: Path) -> dict[str, str]:
    """``suite`` copied to ``dest`` with its first YES/NO label flipped; the item as it is now written."""
    shutil.copytree(suite, dest)
    lines = (dest / "items.jsonl").read_text().splitlines()
    index = next(i for i, line in enumerate(lines) if json.loads(line)["answer_format"] == "yes_no")
    item = json.loads(lines[index])
    item["answer"] = {"YES": "NO", "NO": "YES"}[item["answer"]]
    lines[index] = json.dumps(item)
    (dest / "items.jsonl").write_text("\n".join(lines) + "\n")
    return item


async def test_made_items_are_rederived_from_their_saved_projects_and_a_flipped_label_is_caught(
    pool: EditorPool, made: tuple[Path, int], tmp_path: Path
) -> None:
    from scratchworld_dist.kinds.perception.items._validate import validate_perception_suite

    root, count = made
    suite = load_perception_suite(root)
    assert not suite.problems and len(suite.items) == count >= 25
    kinds = {view.id.rsplit("-", 1)[1] for view in suite.views}
    assert kinds == {"plain", "cut", "zoom_out", "pull_off", "cover", "beside_slot"}
    answers = Counter((item.kind, item.answer) for item in suite.items if item.answer_format == "yes_no")
    for kind in ("connection", "existence", "field"):
        assert answers[(kind, "YES")] == answers[(kind, "NO")] > 0
    assert max(Counter(item.view for item in suite.items).values()) <= 6

    checks = await validate_perception_suite(suite, pool=pool)
    assert [item.problem for check in checks for item in check.items if not item.valid] == []
    assert sum(len(check.items) for check in checks) == count
    assert all(check.pixels_differing is not None and check.pixels_differing < 0.05 for check in checks)

    item = flipped_copy(root, tmp_path / "flipped")
    checks = await validate_perception_suite(load_perception_suite(tmp_path / "flipped"), pool=pool)
    invalid = [(i.item_id, i.problem) for check in checks for i in check.items if not i.valid]
    right = {"YES": "NO", "NO": "YES"}[item["answer"]]
    assert invalid == [(item["id"], f"its answer is {item['answer']!r} but the view gives {right!r}")]


@pytest.mark.browser
def test_validate_exits_1_naming_the_flipped_item(made: tuple[Path, int], tmp_path: Path) -> None:
    item = flipped_copy(made[0], tmp_path / "flipped")
    done = invoke("perception", "validate", str(tmp_path / "flipped"), "--views", item["view"])
    assert done.returncode == 1, done.stderr
    assert f"INVALID {item['id']}: its answer is" in done.stderr
    assert re.search(r"\b1 of \d+ item\(s\) invalid", done.stderr), done.stderr


def test_the_shipped_suite_loads_and_meets_its_composition_target() -> None:
    suite = load_perception_suite(SHIPPED)
    assert suite.kind == "scratchworld_dist" and not suite.problems
    items = suite.items
    assert len(items) >= 300
    answers = Counter((item.kind, item.answer) for item in items if item.answer_format == "yes_no")
    for kind in ("connection", "existence", "field"):
        assert answers[(kind, "YES")] == answers[(kind, "NO")] >= 30
    tags = Counter(item.tag for item in items)
    for tag in ("connection_no_hard", "existence_yes_occluded", "existence_yes_unidentifiable", "exact_match_numeric"):
        assert tags[tag] >= 5, tag
    assert all(item.fact is not None and item.view is not None and task_id_problem(item.id) is None for item in items)
    assert all(re.fullmatch(r"[A-Za-z0-9._-]{1,128}", item.id) for item in items)
    per_view = Counter(item.view for item in items)
    assert max(per_view.values()) <= 10
    sources = {view.source.split("/")[0] for view in suite.views}
    assert len(sources) >= 10  # spread over the task projects, not a few of them
    size = sum(p.stat().st_size for p in SHIPPED.rglob("*") if p.is_file())
    assert size < 10 * 1024 * 1024


@pytest.mark.browser
async def test_the_shipped_suite_holds_on_a_sample_of_views(pool: EditorPool) -> None:
    """One view of each kind (the whole suite is checked by `perception validate`, by hand)."""
    from scratchworld_dist.kinds.perception.items._validate import validate_perception_suite

    suite = load_perception_suite(SHIPPED)
    sample = {}
    for view in suite.views:
        sample.setdefault(view.id.rsplit("-", 1)[1], view.id)
    checks = await validate_perception_suite(suite, views=list(sample.values()), pool=pool)
    assert len(checks) == len(sample) >= 4
    assert [item.problem for check in checks for item in check.items if not item.valid] == []
