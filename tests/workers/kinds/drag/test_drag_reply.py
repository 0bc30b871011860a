"""The drag benchmark's model side: replies shaped like real GPT, Claude, Qwen and UI-TARS output read
as one drag, hostile replies read cheaply, the prompt of each setting and convention, and the start marker."""

from __future__ import annotations

import base64
import time

import cv2
import numpy as np
import pytest

from workers.kinds.drag._prompts import ANSWER_FORMAT, KNOWLEDGE, MARKER_RADIUS, drag_messages, draw_start_marker
from workers.kinds.drag._reply import MAX_SCAN, ParsedDrag, parse_drag_reply

FENCE = "```"
INDICES = {4: (88.0, 305.5), 12: (640.0, 360.0)}
"""Element centres in page px, as the caller builds them from the shown element list."""

OK_CASES: list[tuple[str, str, tuple[float, float], tuple[float, float]]] = [
    (
        "canonical",
        "drag(start_point='<point>62 312</point>', end_point='<point>431 262</point>')",
        (62, 312),
        (431, 262),
    ),
    (
        "gpt_reasoning_then_call",
        "The 'move (10) steps' block is in the palette near (85, 310). To attach it below 'when green flag clicked' "
        "at (420, 230), I grab its left edge and drop so its top-left notch meets the hat's bottom-left.\n\n"
        "drag(start_point='<point>62 312</point>', end_point='<point>431 262</point>')",
        (62, 312),
        (431, 262),
    ),
    (
        "gpt_draft_then_corrected_call",
        "First guess: drag(start_point='<point>90 312</point>', end_point='<point>431 262</point>'). But x=90 is "
        "the number field, which would not drag the block. Corrected:\n"
        "drag(start_point='<point>58.5 311.5</point>', end_point='<point>427.5 261</point>')",
        (58.5, 311.5),
        (427.5, 261),
    ),
    (
        "claude_markdown_fence",
        "## Analysis\nThe **repeat** block's mouth is at about (540, 250).\n\n**Action:**\n"
        f'{FENCE}python\ndrag(start_point="<point>540 230</point>", end_point="<point>612 288</point>")\n{FENCE}\n'
        "This places the block inside the loop.",
        (540, 230),
        (612, 288),
    ),
    (
        "qwen_normalized_point_tags",
        "drag(start_point='<point>254 431</point>', end_point='<point>512 388</point>')",
        (254, 431),
        (512, 388),
    ),
    (
        "qwen_json_in_fence",
        f'{FENCE}json\n{{"action": "drag", "start_point": [254, 431], "end_point": [512, 388]}}\n{FENCE}',
        (254, 431),
        (512, 388),
    ),
    (
        "ui_tars_start_box",
        "Thought: I need to drag the say block under the hat block.\nAction: drag(start_box='(321,455)', "
        "end_box='(644,397)')",
        (321, 455),
        (644, 397),
    ),
    (
        "ui_tars_box_tokens_and_box_centre",
        "Action: drag(start_box='<|box_start|>(300,440,340,470)<|box_end|>', "
        "end_box='<|box_start|>(644,397)<|box_end|>')",
        (320, 455),
        (644, 397),
    ),
    (
        "json_xy_objects",
        f'{FENCE}\n{{"start": {{"x": 100, "y": 200}}, "end": {{"x": 300.5, "y": 400}}}}\n{FENCE}',
        (100, 200),
        (300.5, 400),
    ),
    ("json_flat_keys", '{"action":"drag","start_x":11,"start_y":22,"end_x":33,"end_y":44}', (11, 22), (33, 44)),
    ("json_truncated", 'Answer: {"start_point": [1, 2], "end_point": [3, 4', (1, 2), (3, 4)),
    ("unquoted_tags", "drag(start_point=<point>1 2</point>, end_point=<point>3 4</point>)", (1, 2), (3, 4)),
    (
        "tag_with_comma",
        "drag(start_point='<point>100,200</point>', end_point='<point>300,400</point>')",
        (100, 200),
        (300, 400),
    ),
    (
        "tag_with_brackets",
        "drag(start_point='<point>(100, 200)</point>', end_point='<point>[300,400]</point>')",
        (100, 200),
        (300, 400),
    ),
    ("parenthesised_points", "drag(start_point=(100.5, 200), end_point=(300, 400))", (100.5, 200), (300, 400)),
    ("from_to_keywords", "drag(from=(1, 2), to=(3, 4))", (1, 2), (3, 4)),
    ("start_end_keywords", "drag(start=[5, 6], end=[7, 8])", (5, 6), (7, 8)),
    ("bare_numbers", "drag(10, 20, 30, 40)", (10, 20), (30, 40)),
    ("x1_y1_keywords", "drag(x1=10, y1=20, x2=30, y2=40)", (10, 20), (30, 40)),
    ("prose_labels", "**Start point:** (100, 200)\n**End point:** (300, 400)", (100, 200), (300, 400)),
    ("two_bare_tags", "<point>1 2</point> then <point>3 4</point>", (1, 2), (3, 4)),
    (
        "think_trace_ignored",
        "<think>maybe drag(start_point='<point>9 9</point>', end_point='<point>9 9</point>')</think>"
        "Start point: (1, 2)\nEnd point: (3, 4)",
        (1, 2),
        (3, 4),
    ),
    (
        "draft_in_think_when_answer_has_none",
        "<think>drag(start_point='<point>9 8</point>', end_point='<point>7 6</point>')</think>Done.",
        (9, 8),
        (7, 6),
    ),
    ("off_screen_is_the_callers_check", "drag(start_point='<point>-20 1500</point>', end=(3, 4))", (-20, 1500), (3, 4)),
]


@pytest.mark.parametrize(("reply", "start", "end"), [case[1:] for case in OK_CASES], ids=[c[0] for c in OK_CASES])
def test_replies_read_as_one_drag(reply: str, start: tuple[float, float], end: tuple[float, float]) -> None:
    parsed = parse_drag_reply(reply)
    assert (parsed.parse, parsed.start, parsed.end) == ("ok", start, end), parsed.detail
    assert not parsed.start_in_page and not parsed.end_in_page
    assert parsed.start_index is None and parsed.end_index is None


def test_index_answers_resolve_to_element_centres_in_page_px() -> None:
    parsed = parse_drag_reply("drag(start_point='<index>4</index>', end_point='<index>12</index>')", indices=INDICES)
    assert parsed == ParsedDrag(
        parse="ok", start=(88.0, 305.5), end=(640.0, 360.0), start_index=4, end_index=12, start_in_page=True,
        end_in_page=True,
    )  # fmt: skip


@pytest.mark.parametrize(
    "reply",
    [
        "drag(start_index=4, end_point='<point>431 262</point>')",
        f'{FENCE}json\n{{"api": "drag_and_drop", "args": {{"start_index": 4, "end_x": 431, "end_y": 262}}}}\n{FENCE}',
        'Thus: {"start": "<index>4</index>", "end": [431, 262]}',
    ],
)
def test_an_index_and_a_point_mix(reply: str) -> None:
    parsed = parse_drag_reply(reply, indices=INDICES)
    assert (parsed.parse, parsed.start, parsed.end) == ("ok", (88.0, 305.5), (431.0, 262.0))
    assert (parsed.start_index, parsed.start_in_page, parsed.end_in_page) == (4, True, False)


def test_two_bare_integers_are_indices() -> None:
    parsed = parse_drag_reply("drag(4, 12)", indices=INDICES)
    assert (parsed.parse, parsed.start_index, parsed.end_index) == ("ok", 4, 12)


@pytest.mark.parametrize(
    ("reply", "indices", "detail"),
    [
        ("drag(start_point='<index>4</index>', end_point='<index>99</index>')", INDICES, "end index 99"),
        ("drag(start_index=4, end_index=12)", None, "no element list was shown"),
    ],
)
def test_an_unknown_index_is_bad_index(reply: str, indices: dict | None, detail: str) -> None:
    parsed = parse_drag_reply(reply, indices=indices)
    assert parsed.parse == "bad_index"
    assert detail in parsed.detail
    assert parsed.end is None


@pytest.mark.parametrize("reply", ["", "   \n\t "])
def test_an_empty_reply_is_no_answer(reply: str) -> None:
    assert parse_drag_reply(reply).parse == "no_answer"


@pytest.mark.parametrize(
    "reply",
    [
        "I cannot tell where the blocks are from this screenshot.",
        f"drag(start_point='<point>x y</point>', end_point='<point>x y</point>')  # {ANSWER_FORMAT}",
        "drag(start_point='<point>100</point>', end_point='<point>300 400</point>')",
        "drag(start_point='<point>62 312</point>')",
        '{"action": "click", "x": 62, "y": 312}',
        '{"start_point": [1e999, 2], "end_point": [3, 4]}',
        "drag(start_point='<point>1 2</point>', end_point='<point>" + "9" * 400 + " 4</point>')",
    ],
    ids=["prose", "format_echo", "one_number", "no_end", "click", "infinite", "too_many_digits"],
)
def test_malformed_replies_are_unparsed_with_a_reason(reply: str) -> None:
    parsed = parse_drag_reply(reply)
    assert (parsed.parse, parsed.start, parsed.end) == ("unparsed", None, None)
    assert parsed.detail and "\n" not in parsed.detail


HOSTILE = {
    "braces": "{" * 1_000_000,
    "nested_braces": "{" * 30_000 + "}" * 30_000,
    "calls": "drag(" * 200_000,
    "tags": "<point>" * 200_000,
    "parens": "(" * 500_000,
    "deep_json": '{"start_point":' + "[" * 100_000,
    "keywords": "start=" * 150_000,
    "quotes": "{'" * 300_000,
    "think": "<think>" * 100_000,
    "spaces": "drag" + " " * 1_000_000,
}


@pytest.mark.parametrize("reply", list(HOSTILE.values()), ids=list(HOSTILE))
def test_hostile_replies_are_read_quickly_without_raising(reply: str) -> None:
    # This thread's CPU time, not wall time: a regex that backtracks burns CPU, while a loaded machine only
    # delays us; and not the process's, which counts threads other tests left running (Ray's, servers').
    started = time.thread_time()
    parsed = parse_drag_reply(reply)
    assert time.thread_time() - started < 1.0
    assert parsed.parse == "unparsed"


def test_only_the_end_of_a_huge_reply_is_read() -> None:
    answer = "drag(start_point='<point>1 2</point>', end_point='<point>3 4</point>')"
    assert parse_drag_reply("x" * 5 * MAX_SCAN + answer).start == (1, 2)
    assert parse_drag_reply(answer + "x" * MAX_SCAN).parse == "unparsed"


PNG = cv2.imencode(".png", np.full((720, 1280, 3), 255, np.uint8))[1].tobytes()


def _text(messages: list[dict]) -> tuple[str, str]:
    return messages[0]["content"], messages[1]["content"][0]["text"]


@pytest.mark.parametrize(
    ("system", "phrases"),
    [
        ("pixels", ["pixels of the screenshot", "1279", "719"]),
        ("normalized_1000", ["0-1000", "(1000, 1000)"]),
        ("smart_resize", ["1288x728", "1287", "727"]),
    ],
)
def test_the_prompt_states_the_models_convention(system: str, phrases: list[str]) -> None:
    messages = drag_messages("Drag A below B", "baseline", PNG, system, gt_start_model=None, element_text=None)  # type: ignore[arg-type]
    system_text, user_text = _text(messages)
    for phrase in phrases:
        assert phrase in system_text
    assert ANSWER_FORMAT in system_text
    assert "Drag A below B" in user_text
    assert "red ring" not in system_text + user_text
    assert "<index>" not in system_text


def test_gt_start_states_the_point_in_model_coordinates() -> None:
    messages = drag_messages(
        "Drag A", "gt_start", PNG, "normalized_1000", gt_start_model=(412.5, 300.0), element_text=None
    )
    _, user_text = _text(messages)
    assert "red ring" in user_text
    assert "<point>412.5 300</point>" in user_text


def test_the_screenshot_is_an_image_part() -> None:
    messages = drag_messages("Drag A", "baseline", PNG, "pixels", gt_start_model=None, element_text=None)
    assert [message["role"] for message in messages] == ["system", "user"]
    image = messages[1]["content"][1]
    assert image["type"] == "image_url"
    prefix = "data:image/png;base64,"
    assert image["image_url"]["url"].startswith(prefix)
    assert base64.b64decode(image["image_url"]["url"][len(prefix) :]) == PNG


def test_the_element_list_and_index_answers_are_offered_together() -> None:
    listing = "0  blocks  motion_movesteps  (40, 300) 96x40"
    system_text, user_text = _text(
        drag_messages("Drag A", "baseline", PNG, "pixels", gt_start_model=None, element_text=listing)
    )
    assert listing in user_text
    assert "<index>N</index>" in system_text
    assert "1280x720" in system_text


def test_knowledge_hints_come_with_the_knowledge_setting_only() -> None:
    with_hints, _ = _text(drag_messages("Drag A", "knowledge", PNG, "pixels", gt_start_model=None, element_text=None))
    without, _ = _text(drag_messages("Drag A", "baseline", PNG, "pixels", gt_start_model=None, element_text=None))
    assert KNOWLEDGE in with_hints
    assert KNOWLEDGE not in without
    assert "top-left corner" in KNOWLEDGE and "palette deletes" in KNOWLEDGE


@pytest.mark.parametrize(
    ("setting", "point"), [("gt_start", None), ("baseline", (1.0, 2.0)), ("knowledge", (1.0, 2.0))]
)
def test_a_start_point_is_given_exactly_for_gt_start(setting: str, point: tuple[float, float] | None) -> None:
    with pytest.raises(ValueError, match="gt_start"):
        drag_messages("Drag A", setting, PNG, "pixels", gt_start_model=point, element_text=None)  # type: ignore[arg-type]


def test_the_start_marker_is_a_red_ring_around_the_point() -> None:
    marked = cv2.imdecode(np.frombuffer(draw_start_marker(PNG, (200, 150)), np.uint8), cv2.IMREAD_COLOR)
    assert marked.shape == (720, 1280, 3)
    for x, y in ((200 + MARKER_RADIUS, 150), (200, 150 - MARKER_RADIUS), (200 - MARKER_RADIUS, 150)):
        blue, green, red = (int(channel) for channel in marked[y, x])
        assert red > 200 and green < 60 and blue < 60, (x, y, marked[y, x])
    assert marked[150, 200].tolist() == [255, 255, 255]  # the point itself stays visible
    assert marked[150, 200 + 3 * MARKER_RADIUS].tolist() == [255, 255, 255]
    assert marked[500, 900].tolist() == [255, 255, 255]
