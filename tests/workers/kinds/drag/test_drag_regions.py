"""Exact drag regions against real drags in a real editor, on our generated suite, boundaries included;
and each connection kind's verification, made and missed."""

from __future__ import annotations

import io
import json
import random
import zipfile

import pytest

from scratchworld_dist.kinds.drag.items import DragTask, load_drag_suite
from tests.conftest import REPO, pooled_editor
from workers.contract import Point
from workers.editor import Editor, EditorPool
from workers.kinds.drag import DragPayload
from workers.kinds.drag import _page as page

pytestmark = [pytest.mark.browser]

SUITE = load_drag_suite(REPO / "drag-tasks")


TASKS = SUITE.one_per_kind()


def project_json(sb3: bytes) -> object:
    """The project itself: the archive's bytes also carry each entry's modification time."""
    with zipfile.ZipFile(io.BytesIO(sb3)) as archive:
        return json.loads(archive.read("project.json"))


async def connects(editor: Editor, payload: DragPayload, start: Point, end: Point) -> tuple[bool, str]:
    await page.set_up(editor, payload)
    before = await page.block_ids(editor)
    await page.drag(editor, start, end)
    return await page.verify(editor, payload, before)


def test_the_suite_covers_every_kind_from_both_sources() -> None:
    kinds = {(t.connection.kind, t.source.kind) for t in SUITE.tasks}
    assert {"next", "parent", "substack_1", "input"} <= {kind for kind, _ in kinds}
    assert {source for _, source in kinds} == {"canvas", "flyout"}
    assert len(SUITE.tasks) >= 60
    assert {t.type for t in SUITE.tasks} == {"T1", "T2"}


@pytest.mark.parametrize("task", TASKS, ids=[f"{t.connection.kind}-{t.source.kind}" for t in TASKS])
async def test_regions_agree_with_real_drags_at_their_edges(shared_pool: EditorPool, task: DragTask) -> None:
    payload = task.payload(task.initial_project.read_bytes())
    rng = random.Random(task.id)
    async with pooled_editor(shared_pool) as editor:
        await page.set_up(editor, payload)
        regions = await page.regions(editor, payload)
        assert not regions.start.empty and not regions.end.empty
        edge, outside = regions.end.boundary()
        for point in rng.sample(edge, 2):
            assert (await connects(editor, payload, regions.fixed_start, point))[0], ("end edge", point)
        for point in rng.sample(outside, 2):
            made, observed = await connects(editor, payload, regions.fixed_start, point)
            assert not made, ("just outside the end region", point)
            assert observed  # a miss says what the drag did instead
        aim = regions.end.deepest()
        offset = (aim[0] - regions.fixed_start[0], aim[1] - regions.fixed_start[1])
        edge, outside = regions.start.boundary()
        for point in rng.sample(edge, 1):  # grabbed at its edge: the block moves with the press, and connects
            assert (await connects(editor, payload, point, (point[0] + offset[0], point[1] + offset[1])))[0]
        for point in rng.sample(outside, 1):  # pressed just off it: the source stays where it was
            assert not (await connects(editor, payload, point, (point[0] + offset[0], point[1] + offset[1])))[0]


# Tasks whose previews push a script near another: Blockly bumps such scripts apart by a random offset
# unless a drag is in progress, which made these regions differ from one computation to the next.
PUSHING = ["quiz_score-initial-next-4ff060e45f", "star_shower-golden-next-9eb2ff3c68", TASKS[0].id]


@pytest.mark.parametrize("task_id", PUSHING)
async def test_regions_are_read_only_and_repeatable(shared_pool: EditorPool, task_id: str) -> None:
    task = SUITE.task(task_id)
    payload = task.payload(task.initial_project.read_bytes())
    async with pooled_editor(shared_pool) as editor:
        await page.set_up(editor, payload)
        before = project_json(await editor.save_project())
        first = await page.regions(editor, payload)
        for _ in range(2):
            again = await page.regions(editor, payload)
            assert (first.start, first.end, first.fixed_start) == (again.start, again.end, again.fixed_start)
        assert project_json(await editor.save_project()) == before


async def test_verification_reads_the_structure_not_the_position(shared_pool: EditorPool) -> None:
    """A drop of the source on the reference's other side (a wrong connection) is a miss, named."""
    task = next(t for t in SUITE.tasks if t.connection.kind == "next" and t.source.kind == "canvas")
    payload = task.payload(task.initial_project.read_bytes())
    async with pooled_editor(shared_pool) as editor:
        await page.set_up(editor, payload)
        regions = await page.regions(editor, payload)
        made, observed = await connects(
            editor, payload, regions.fixed_start, (regions.fixed_start[0] + 4, regions.fixed_start[1] + 60)
        )
        assert not made
        assert "top-level script" in observed or "hangs below" in observed


async def test_a_parent_drag_must_move_the_whole_stack(shared_pool: EditorPool) -> None:
    """Pulling the tail off the source's stack and dropping it by the oracle's offset puts the same tail above
    the reference, but the stack the instruction names stays behind: a miss (upstream's rule would pass it)."""
    task = next(
        t
        for t in SUITE.tasks
        if t.connection.kind == "parent" and t.source.kind == "canvas" and t.source.tail_block_id != t.source.block_id
    )
    payload = task.payload(task.initial_project.read_bytes())
    async with pooled_editor(shared_pool) as editor:
        await page.set_up(editor, payload)
        regions = await page.regions(editor, payload)
        aim = regions.end.deepest()
        offset = (aim[0] - regions.fixed_start[0], aim[1] - regions.fixed_start[1])
        x = regions.fixed_start[0]
        below = max(y for y, x0, x1 in regions.start.rows if x0 <= x <= x1) + 6  # on the block below the source
        assert not regions.start.contains(x, below)
        made, observed = await connects(editor, payload, (x, below), (x + offset[0], below + offset[1]))
        assert not made
        assert f"the dragged {task.source.opcode} is a top-level script" in observed  # the source stayed
        assert (await connects(editor, payload, regions.fixed_start, aim))[0]  # the whole stack, the same offset


async def test_the_end_region_reaches_as_far_as_a_kept_candidate(shared_pool: EditorPool) -> None:
    """Blockly keeps its current candidate past the snap radius while another connection is in reach and not
    much closer: the region's far edge (here its left end, ~50 px from the aim) is where real drags stop connecting."""
    task = SUITE.task("star_shower-golden-substack_1-fee009aff4")
    payload = task.payload(task.initial_project.read_bytes())
    async with pooled_editor(shared_pool) as editor:
        await page.set_up(editor, payload)
        regions = await page.regions(editor, payload)
        leftmost = sorted(regions.end.rows, key=lambda row: row[1])[:2]
        for y, x0, _ in leftmost:
            assert (await connects(editor, payload, regions.fixed_start, (x0, y)))[0], ("far edge", (x0, y))
            assert not (await connects(editor, payload, regions.fixed_start, (x0 - 1, y)))[0], ("past it", (x0 - 1, y))
