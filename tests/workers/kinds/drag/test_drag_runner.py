"""Drag jobs in a real editor with the llm agent against a real local OpenAI-compatible server: the model's
points in its own convention, the gt_start marker, parse failures and model errors each recorded by class."""

from __future__ import annotations

import base64
import json
from collections.abc import AsyncIterator, Iterator

import cv2
import numpy as np
import pytest

from scratchworld_dist.kinds.drag import plan_drag_jobs, read_drag_task
from scratchworld_dist.kinds.drag.items import load_drag_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import REPO
from tests.support.openai_server import OpenAIServer, reply, status
from workers.contract import AgentRef, DragRegions, LLMSettings, ModelSpec, RetryPolicy
from workers.editor import BrowserSession, EditorPool
from workers.kinds.drag import DragPayload, DragSpec
from workers.kinds.drag import _page as page
from workers.kinds.drag._runner import DragRunner

pytestmark = [pytest.mark.usefixtures("litellm_clients"), pytest.mark.browser]

KEY_ENV = "SCRATCHWORLD_TEST_DRAG_KEY"
SECRET = "sk-drag-test-93be1c07aa"
FAST = RetryPolicy(max_attempts=2, initial_backoff_s=0.01, max_backoff_s=0.02, request_timeout_s=10, max_total_s=30)
CONTENT = read_drag_task(next(t for t in load_drag_suite(REPO / "drag-tasks").tasks if t.source.kind == "flyout"))


@pytest.fixture(autouse=True)
def api_key(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv(KEY_ENV, SECRET)


@pytest.fixture
def server() -> Iterator[OpenAIServer]:
    with OpenAIServer() as running:
        yield running


@pytest.fixture(scope="module")
async def runner(session: BrowserSession) -> AsyncIterator[DragRunner]:
    async with EditorPool(session, spare=0) as pool:
        yield DragRunner(pool)


@pytest.fixture(scope="module")
async def regions(runner: DragRunner) -> DragRegions:
    async with runner.pool.editor() as editor:
        await page.set_up(editor, CONTENT.payload)
        return await page.regions(editor, CONTENT.payload)


def spec(server: OpenAIServer, setting: str = "baseline", model: str = "openai/gpt-4o-mini") -> DragSpec:
    model_spec = ModelSpec(name="m", model=model, api_base=server.url, api_key_env=KEY_ENV)
    llm = LLMSettings().model_copy(update={"retry": FAST})
    (job,) = plan_drag_jobs([model_spec], [setting], AgentRef(name="llm"), [CONTENT], [3], llm=llm)  # type: ignore[list-item]
    made = worker_job(job, 1, 120)
    assert isinstance(made, DragSpec)
    return made


def call(start: tuple[float, float], end: tuple[float, float]) -> str:
    return (
        "I will grab the block by its label and drop it under the hat.\n"
        f"drag(start_point='<point>{start[0]:g} {start[1]:g}</point>', "
        f"end_point='<point>{end[0]:g} {end[1]:g}</point>')"
    )


async def test_a_model_answering_in_pixels_makes_the_connection(
    runner: DragRunner, regions: DragRegions, server: OpenAIServer
) -> None:
    server.push(reply(call(regions.fixed_start, regions.end.deepest())))
    result = await runner.run(spec(server), CONTENT.payload)
    assert (result.outcome, result.error_class) == ("passed", None)
    drag = result.detail
    assert drag is not None
    assert (drag.parse, drag.start_in_region, drag.end_in_region, drag.start_error_px) == ("ok", True, True, 0.0)
    assert result.steps[0].llm_calls == 1 and result.steps[0].reply is not None
    assert drag.annotated_sha256 in result.images
    body = server.requests[0].body
    assert "pixels" in str(body["messages"][0]["content"]).lower()
    recorded = json.dumps([step.model_dump(mode="json") for step in result.steps]) + result.detail.model_dump_json()
    assert SECRET not in recorded


async def test_a_qwen_model_answers_in_thousandths(
    runner: DragRunner, regions: DragRegions, server: OpenAIServer
) -> None:
    def thousandths(p: tuple[int, int]) -> tuple[float, float]:
        return round(p[0] * 1000 / 1280, 1), round(p[1] * 1000 / 720, 1)

    server.push(reply(call(thousandths(regions.fixed_start), thousandths(regions.end.deepest()))))
    result = await runner.run(spec(server, model="openai/qwen2.5-vl-72b-instruct"), CONTENT.payload)
    assert result.outcome == "passed"
    assert result.detail is not None and result.detail.start_error_px == 0.0


async def test_gt_start_marks_and_states_the_start_in_the_model_convention(
    runner: DragRunner, regions: DragRegions, server: OpenAIServer
) -> None:
    end = regions.end.deepest()
    missed = (end[0] + 300, end[1] + 200)  # far from any connection
    server.push(reply(call(regions.fixed_start, missed)))
    result = await runner.run(spec(server, setting="gt_start"), CONTENT.payload)
    assert result.outcome == "failed"
    drag = result.detail
    assert drag is not None and drag.gt_start == regions.fixed_start
    assert (drag.start_in_region, drag.end_in_region) == (True, False)
    assert drag.end_error_px is not None and drag.end_error_px > 100
    user = server.requests[0].body["messages"][-1]["content"]
    text = " ".join(part.get("text", "") for part in user)
    assert f"{regions.fixed_start[0]}" in text and f"{regions.fixed_start[1]}" in text
    image = next(part["image_url"]["url"] for part in user if part["type"] == "image_url")
    png = base64.b64decode(image.split(",", 1)[1])
    pixels = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    x, y = regions.fixed_start
    ring = pixels[y - 14 : y + 15, x - 14 : x + 15].reshape(-1, 3)
    assert any(int(r) > 200 and int(g) < 60 and int(b) < 60 for b, g, r in ring)  # the red ring is drawn


async def test_an_unparsable_reply_is_a_failure_by_class_and_nothing_is_dragged(
    runner: DragRunner, server: OpenAIServer
) -> None:
    server.push(reply("I cannot see the block you mean."))
    result = await runner.run(spec(server), CONTENT.payload)
    assert (result.outcome, result.error_class) == ("failed", None)
    assert result.detail is not None and (result.detail.parse, result.detail.start, result.detail.connected) == (
        "unparsed",
        None,
        False,
    )
    assert result.steps[0].error_code == "unparsed"


async def test_a_model_that_keeps_failing_is_an_error_not_a_failure(runner: DragRunner, server: OpenAIServer) -> None:
    server.default = status(500)
    result = await runner.run(spec(server), CONTENT.payload)
    assert (result.outcome, result.error_class) == ("error", "model_provider_error")
    assert server.count == FAST.max_attempts
    assert result.evaluation is None and result.detail is None


async def test_the_oracle_passes_every_setting(runner: DragRunner) -> None:
    for setting in ("baseline", "gt_start", "knowledge"):
        (job,) = plan_drag_jobs([None], [setting], AgentRef(name="oracle"), [CONTENT], [0])  # type: ignore[list-item]
        made = worker_job(job, 1, 120)
        assert isinstance(made, DragSpec)
        result = await runner.run(made, CONTENT.payload)
        assert result.outcome == "passed", (setting, result.error_message)


def test_payloads_ship_the_task_not_its_paths() -> None:
    payload: DragPayload = CONTENT.payload
    assert payload.initial_project[:2] == b"PK"
    assert payload.view == CONTENT.task.view
