"""Evaluations draw the stage on demand: frames nobody looks at are skipped, a picture asked for is right.

The scripts below count the stage's draws by the renderer's clears of the screen (``gl.clear`` on the
default framebuffer), while a sprite moves every frame and nothing senses: every frame draws it under
``every_frame``, none does under ``on_demand``; a snapshot and the canvas's own picture are drawn
when asked for, and show the same pixels under both.
"""

from __future__ import annotations

import base64

import cv2
import numpy as np
import pytest

from scratchworld_dist.sb3 import Project, block, rect_costume
from workers.contract import EvalResult, EvaluationSpec
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import Evaluator

pytestmark = pytest.mark.browser

COUNT_DRAWS = """
module.exports = async (vm) => {
  const gl = vm.renderer.gl;
  let draws = 0;
  const clear = gl.clear;
  gl.clear = function (...args) {
    if (gl.getParameter(gl.FRAMEBUFFER_BINDING) === null) draws += 1;
    return clear.apply(gl, args);
  };
  vm.greenFlag();
  await new Promise((resolve) => setTimeout(resolve, 1000));
  const moved = draws;
  const snapshot = await new Promise((resolve) => vm.renderer.requestSnapshot(resolve));
  const picture = vm.renderer.gl.canvas.toDataURL('image/png');
  gl.clear = clear;
  return {details: [
    {name: 'draws while moving', passed: true, meta: {draws: moved}},
    {name: 'snapshot', passed: snapshot.startsWith('data:image/png'), meta: {png: snapshot}},
    {name: 'canvas picture', passed: picture.startsWith('data:image/png'), meta: {png: picture}},
  ]};
};
"""


def moving_square() -> bytes:
    """A red square that glides right one step per frame, forever, on a white stage."""
    project = Project()
    project.sprite("Square", costume=rect_costume("red", 40, 40, "#ff0000"), x=-100, y=0).script(
        block("event_whenflagclicked"), block("control_forever", SUBSTACK=[block("motion_changexby", DX=2)])
    )
    return project.to_sb3()


async def evaluate(evaluator: Evaluator, render: str) -> EvalResult:
    spec = EvaluationSpec(script_name="draws.js", script_source=COUNT_DRAWS, timeout_s=30, clock="virtual")
    return await evaluator.evaluate(moving_square(), spec.model_copy(update={"render": render}))


def pixels(data_url: str) -> np.ndarray:
    png = base64.b64decode(data_url.split(",", 1)[1])
    image = cv2.imdecode(np.frombuffer(png, np.uint8), cv2.IMREAD_COLOR)
    assert image is not None
    return image


async def test_frames_nobody_looks_at_are_not_drawn_and_a_picture_asked_for_is_right(evaluator: Evaluator) -> None:
    every = await evaluate(evaluator, "every_frame")
    demand = await evaluate(evaluator, "on_demand")
    for result, render in ((every, "every_frame"), (demand, "on_demand")):
        assert result.error is None, result.error
        assert result.conditions is not None and result.conditions.render == render
        assert result.success
    assert every.tests[0].meta["draws"] >= 25  # ~30 frames in a simulated second  # type: ignore[index]
    assert demand.tests[0].meta["draws"] == 0  # type: ignore[index]
    # The snapshot and the canvas show the square where the VM has it, the same pixels either way.
    for index in (1, 2):
        drawn = pixels(every.tests[index].meta["png"])  # type: ignore[index,arg-type]
        asked = pixels(demand.tests[index].meta["png"])  # type: ignore[index,arg-type]
        assert drawn.shape == asked.shape
        assert np.abs(drawn.astype(int) - asked.astype(int)).max() <= 2
        red = (asked[:, :, 2] > 200) & (asked[:, :, 1] < 60) & (asked[:, :, 0] < 60)
        assert red.sum() > 100  # the square is in the picture


async def test_a_page_after_an_on_demand_evaluation_recycles_clean_and_draws_every_frame_again(
    session: BrowserSession,
) -> None:
    """(A pool of its own: an editor of the shared one may retire at its use limit between the two.)"""
    async with EditorPool(session, spare=0) as pool:
        evaluator = Evaluator(session, pool)
        await evaluate(evaluator, "on_demand")
        again = await evaluate(evaluator, "every_frame")
        assert (pool.opened, pool.reused, dict(pool.discarded)) == (1, 1, {})  # the same page served again
    assert again.tests[0].meta["draws"] >= 25  # type: ignore[index]
