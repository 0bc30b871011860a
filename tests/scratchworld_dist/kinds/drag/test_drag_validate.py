"""``scratchworld drag validate``: a drag suite's tasks checked in a real editor, invalid ones named."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from scratchworld_dist.kinds.drag.items import load_drag_suite
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from workers.contract import DragRegions

pytestmark = [pytest.mark.browser]

GOOD = "double_each_letter-initial-next-bda30b8d49"
BROKEN = "arrow_key_walker-golden-next-3334e74207"


def test_valid_tasks_keep_their_regions_and_a_broken_one_fails_the_suite(tmp_path: Path) -> None:
    suite = tmp_path / "suite"
    shutil.copytree(REPO / "drag-tasks", suite)
    path = suite / "tasks" / f"{BROKEN}.json"
    task = json.loads(path.read_text())
    task["connection"]["kind"] = "parent"  # the hat "when green flag clicked" cannot hang below anything
    path.write_text(json.dumps(task))
    out = tmp_path / "checks.json"

    done = invoke("drag", "validate", str(suite), "--tasks", f"{GOOD},{BROKEN}", "--json", str(out))

    assert done.returncode == 1, done.stderr
    assert "1 of 2 drag task(s) invalid" in " ".join(done.stderr.split())
    good, broken = json.loads(out.read_text())
    assert (good["task_id"], good["valid"], broken["task_id"], broken["valid"]) == (GOOD, True, BROKEN, False)
    assert "hangs below event_whenflagclicked" in good["detail"]
    assert "no connection for parent" in broken["detail"] and broken["regions"] is None
    regions = DragRegions.model_validate(good["regions"])
    assert regions.start.contains(*regions.fixed_start) and not regions.end.empty


def test_the_shipped_suite_is_valid_on_a_sample() -> None:
    """One task of each connection kind and source (the whole suite is the drag demo's oracle run)."""
    sample = load_drag_suite(REPO / "drag-tasks").one_per_kind()
    done = invoke("drag", "validate", str(REPO / "drag-tasks"), "--tasks", ",".join(t.id for t in sample))
    assert done.returncode == 0, done.stderr
    assert f"all {len(sample)} drag task(s) valid" in done.stderr
