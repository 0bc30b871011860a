"""Regions as data, the scripted drag agents, and the jitter agent against the theory of its noise."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from workers.agents._model_calls import EpisodeModels
from workers.contract import AgentRef, AgentUnavailableError, DragRegions, Region, RetryPolicy
from workers.kinds.drag._agents import DragQuestion, drag_agent
from workers.kinds.drag._annotate import annotate


def rectangle(x0: int, y0: int, x1: int, y1: int) -> Region:
    return Region(rows=tuple((y, x0, x1) for y in range(y0, y1 + 1)))


START = rectangle(100, 100, 139, 119)  # 40 x 20 px
END = rectangle(300, 200, 329, 211)  # 30 x 12 px
REGIONS = DragRegions(start=START, fixed_start=START.deepest(), end=END)
MODELS = EpisodeModels(RetryPolicy(), seed=0)


def question(seed: int, gt_start: tuple[int, int] | None = None) -> DragQuestion:
    return DragQuestion(
        task_id="t",
        instruction="i",
        setting="baseline",
        screenshot_png=b"",
        seed=seed,
        gt_start=gt_start,
        regions=REGIONS,
    )


def test_region_geometry() -> None:
    assert (START.area, START.contains(100, 100), START.contains(99.6, 100), START.contains(99, 100)) == (
        800,
        True,
        True,
        False,
    )
    assert START.distance(95, 110) == 5
    assert START.distance(136 + 10 + 3, 119 + 4) == pytest.approx(math.hypot(10, 4))
    assert START.deepest() in {(119, 109), (120, 110), (119, 110), (120, 109)}
    ring = Region(rows=((0, 0, 4), (1, 0, 0), (1, 4, 4), (2, 0, 4)))  # a hollow square: no pixel is deep
    assert ring.contains(*ring.deepest())
    block = Region(rows=((0, 0, 2), (1, 0, 2), (2, 0, 2)))  # 3x3: all but its centre is rim
    rim, around = block.boundary()
    assert (1, 1) not in rim and len(rim) == 8 and set(rim) <= set(block.points())
    assert len(around) == 12 and not set(around) & set(block.points()) and (-1, 1) in around and (3, 3) not in around
    assert Region().distance(0, 0) == math.inf
    with pytest.raises(ValueError, match="empty region"):
        Region().deepest()


async def test_the_oracle_aims_at_the_deepest_pixels() -> None:
    answer = await drag_agent(AgentRef(name="oracle")).answer(question(0), None, MODELS)
    assert answer.start == REGIONS.fixed_start
    assert answer.end == END.deepest()


def expected_hits(region: Region, centre: tuple[float, float], sigma: float) -> float:
    """The chance a Gaussian aim at ``centre`` lands on a pixel of ``region`` (rounded to the nearest pixel)."""
    total = 0.0
    for y, x0, x1 in region.rows:
        py = math.erf((y + 0.5 - centre[1]) / (sigma * math.sqrt(2))) - math.erf(
            (y - 0.5 - centre[1]) / (sigma * math.sqrt(2))
        )
        px = math.erf((x1 + 0.5 - centre[0]) / (sigma * math.sqrt(2))) - math.erf(
            (x0 - 0.5 - centre[0]) / (sigma * math.sqrt(2))
        )
        total += py * px / 4
    return total


@pytest.mark.parametrize("sigma", [2.0, 8.0, 20.0])
async def test_jitter_hits_the_regions_as_often_as_its_noise_predicts(sigma: float) -> None:
    agent = drag_agent(AgentRef(name="jitter", params={"sigma_px": sigma}))
    runs = 400
    starts = ends = 0
    for seed in range(runs):
        answer = await agent.answer(question(seed), None, MODELS)
        assert answer.start is not None and answer.end is not None
        starts += START.contains(*answer.start)
        fixed = REGIONS.fixed_start
        moved = (answer.end[0] + fixed[0] - answer.start[0], answer.end[1] + fixed[1] - answer.start[1])
        ends += END.contains(*moved)
    for hits, region, centre in ((starts, START, REGIONS.fixed_start), (ends, END, END.deepest())):
        p = expected_hits(region, centre, sigma)
        tolerance = 4 * math.sqrt(p * (1 - p) / runs) + 0.02  # 4 standard errors, and rounding of the points
        assert abs(hits / runs - p) <= tolerance, (sigma, hits / runs, p)


async def test_jitter_keeps_a_given_start_and_is_reproducible() -> None:
    agent = drag_agent(AgentRef(name="jitter", params={"sigma_px": 10}))
    given = await agent.answer(question(3, gt_start=REGIONS.fixed_start), None, MODELS)
    assert given.start == REGIONS.fixed_start
    assert (await agent.answer(question(5), None, MODELS)) == (await agent.answer(question(5), None, MODELS))
    assert (await agent.answer(question(5), None, MODELS)) != (await agent.answer(question(6), None, MODELS))


@pytest.mark.parametrize(
    ("ref", "message"),
    [
        (AgentRef(name="noop"), r"not registered for the drag benchmark \(registered: jitter, llm, oracle\)"),
        (AgentRef(name="jitter", params={"sigma_px": -1}), "sigma_px"),
        (AgentRef(name="oracle", params={"x": 1}), r"agent oracle takes no params \(given: x\)"),
        (AgentRef(name="always_yes"), "'always_yes' is an agent of perception"),
        (AgentRef(name="workers.kinds.perception._agents:AlwaysYesAgent"), "serves perception, not drag"),
    ],
)
def test_unknown_agents_and_bad_params_are_named(ref: AgentRef, message: str) -> None:
    with pytest.raises(AgentUnavailableError, match=message):
        drag_agent(ref)


def test_the_annotated_screenshot_shows_regions_and_points() -> None:
    blank = cv2.imencode(".png", np.full((720, 1280, 3), 255, np.uint8))[1].tobytes()
    start, end = (110.0, 105.0), (315.0, 200.0)
    image = cv2.imdecode(np.frombuffer(annotate(blank, REGIONS, start, end), np.uint8), cv2.IMREAD_COLOR)
    b, g, r = (int(v) for v in image[115, 135])  # start region, away from the dot: tinted green
    assert g > r and g > b
    shift = (round(start[0]) - REGIONS.fixed_start[0], round(start[1]) - REGIONS.fixed_start[1])
    b, g, r = (int(v) for v in image[211 + shift[1], 329 + shift[0] - 1])  # end region, moved with the press
    assert b > r
    b, g, r = (int(v) for v in image[105, 110])  # the press: a red dot
    assert r > 200 and g < 50 and b < 50
