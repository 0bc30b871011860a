"""Perception items without a browser: upstream's layout read in place, our format written and read back, bad
files left out with a problem naming them, both scorings on hand-made replies, and the answering prompt."""

from __future__ import annotations

import base64
import json
import shutil
from collections import Counter
from pathlib import Path

import pytest

from scratchworld_dist._errors import SuiteError
from scratchworld_dist.kinds.perception.items import (
    PerceptionItem,
    load_perception_suite,
    read_screenshot,
    write_perception_suite,
)
from tests.support.perception_suites import ITEMS, png, write_suite
from workers.kinds.perception import perception_messages, score_reply, strict_correct


def upstream_task(task_id: str, **fields: object) -> dict[str, object]:
    task: dict[str, object] = {
        "task_id": task_id,
        "instruction": "Is there any `say` block that is visible in the canvas?",
        "screenshot": "001.png",
        "task_type": "existence",
        "tag": "existence_yes_clear",
        "ground_truth": "YES",
        "prompt": [{"role": "system", "content": "generate ONE question"}],
        "response_content": "Question: ...\nAnswer: YES",
    }
    task.update(fields)
    return task


def fake_clone(root: Path, tasks: dict[str, object]) -> Path:
    base = root / "visual_perception_benchmark"
    (base / "tasks").mkdir(parents=True)
    (base / "screenshots_final").mkdir()
    (base / "screenshots_final" / "001.png").write_bytes(png(10))
    for name, task in tasks.items():
        text = task if isinstance(task, str) else json.dumps(task)
        (base / "tasks" / name).write_text(text)
    return root


def test_an_upstream_layout_is_read_in_place_with_bad_files_left_out_and_named(tmp_path: Path) -> None:
    clone = fake_clone(
        tmp_path,
        {
            "2.json": upstream_task("2"),
            "10.json": upstream_task(
                "10",
                task_type="field",
                tag="exact_match_numeric",
                instruction="What text is shown in the text field of the `say` block?",
                ground_truth=" Hello! ",
            ),
            "11.json": upstream_task("11", task_type="field", tag="exact_match_dropdown", ground_truth="left arrow",
                                     instruction="Which key does the hat wait for?"),
            "3.json": upstream_task("3", ground_truth="no"),
            "4.json": upstream_task("4", screenshot="404.png"),
            "5.json": upstream_task("5", screenshot="../../secret.png"),
            "6.json": upstream_task("6", task_type="colour"),
            "7.json": "{not json",
        },
    )  # fmt: skip
    suite = load_perception_suite(clone / "visual_perception_benchmark")  # the benchmark folder or the clone
    assert suite.kind == "upstream"
    assert [item.id for item in suite.items] == ["vp_002", "vp_003", "vp_010", "vp_011"]  # by number, not name
    by_id = {item.id: item for item in suite.items}
    assert (by_id["vp_003"].answer_format, by_id["vp_003"].answer) == ("yes_no", "NO")  # upstream's case folded
    text = by_id["vp_010"]
    assert (text.answer_format, text.value_kind, text.answer) == ("value", "text", "Hello!")  # by its wording
    assert by_id["vp_011"].value_kind == "dropdown"  # by the tag when the wording says nothing
    assert by_id["vp_002"].upstream is not None and by_id["vp_002"].upstream.task_id == "2"
    assert "generate" not in by_id["vp_002"].model_dump_json()  # the generating prompt is not kept
    problems = {Path(str(p.path)).name: p.message for p in suite.problems}
    assert set(problems) == {"4.json", "5.json", "6.json", "7.json"}
    assert "404.png does not exist" in problems["4.json"] and "is not a file name" in problems["5.json"]
    assert "task_type" in problems["6.json"] and "malformed JSON" in problems["7.json"]
    assert all("\n" not in message for message in problems.values())


def test_a_folder_that_is_no_perception_suite_is_one_line(tmp_path: Path) -> None:
    with pytest.raises(SuiteError, match="not a perception suite") as caught:
        load_perception_suite(tmp_path)
    assert "\n" not in str(caught.value)
    with pytest.raises(SuiteError, match="no such directory"):
        load_perception_suite(tmp_path / "missing")


@pytest.mark.upstream
def test_upstreams_200_items_load_with_their_kinds_and_answers(upstream_dir: Path) -> None:
    suite = load_perception_suite(upstream_dir)
    assert len(suite.items) == 200 and not suite.problems
    assert Counter(item.kind for item in suite.items) == {"connection": 60, "existence": 80, "field": 60}
    values = [item for item in suite.items if item.answer_format == "value"]
    assert len(values) == 30 and {item.value_kind for item in values} == {"number", "text", "dropdown"}
    yes = sum(item.answer == "YES" for item in suite.items)
    assert yes == 86  # the YES share always_yes must score
    assert len({item.screenshot for item in suite.items}) == 149
    assert all(read_screenshot(item.screenshot).startswith(b"\x89PNG") for item in suite.items[:5])


def test_our_format_reads_back_what_was_written(tmp_path: Path) -> None:
    suite = load_perception_suite(write_suite(tmp_path / "suite"))
    assert suite.kind == "scratchworld_dist" and not suite.problems
    assert [(i.id, i.kind, i.tag, i.answer, i.value_kind) for i in suite.items] == [
        (item_id, kind, tag, answer, value_kind) for item_id, kind, tag, _, value_kind, answer in ITEMS
    ]
    shots = {item.screenshot for item in suite.items}
    assert len(shots) == 3 and all(path.parent == suite.root / "screenshots" for path in shots)  # once per image
    with pytest.raises(SuiteError, match="not empty"):
        write_perception_suite(list(suite.items), [], tmp_path / "suite", "again")


def test_bad_lines_of_our_format_are_left_out_naming_their_line(tmp_path: Path) -> None:
    root = write_suite(tmp_path / "suite")
    lines = (root / "items.jsonl").read_text().splitlines()
    first = json.loads(lines[0])
    lines[1] = json.dumps({**first, "id": "escape", "screenshot": "../../etc/passwd"})
    lines[2] = json.dumps({**first, "id": "maybe", "answer": "MAYBE"})
    lines[3] = json.dumps(first)  # the first item again
    lines[4] = json.dumps({**first, "id": "viewed", "view": "nowhere"})
    lines[5] = json.dumps({**first, "id": "not plain!"})
    (root / "items.jsonl").write_text("\n".join(lines) + "\n")
    suite = load_perception_suite(root)
    assert [item.id for item in suite.items] == ["c-yes", "f-text", "f-eq"]
    problems = {str(problem.path).rsplit("/", 1)[-1]: problem.message for problem in suite.problems}
    assert "outside the suite folder" in problems["items.jsonl:2"]
    assert "YES or NO, not 'MAYBE'" in problems["items.jsonl:3"]
    assert "listed twice" in problems["items.jsonl:4"]
    assert "not a view of the suite" in problems["items.jsonl:5"]
    assert "not a plain name" in problems["items.jsonl:6"]
    (root / "items.jsonl").write_text("\n".join(lines[:5]) + "\n")  # three lines short
    counted = load_perception_suite(root).problems
    assert any("holds 5 line(s); perception-suite.json says 8" in problem.message for problem in counted)


def test_a_screenshot_that_is_not_a_png_is_refused_naming_it(tmp_path: Path) -> None:
    root = write_suite(tmp_path / "suite")
    item = load_perception_suite(root).items[0]
    item.screenshot.write_bytes(b"GIF89a not a png")
    with pytest.raises(SuiteError, match="not a PNG image") as caught:
        read_screenshot(item.screenshot)
    assert str(item.screenshot) in str(caught.value)
    shutil.rmtree(root / "screenshots")
    assert len(load_perception_suite(root).problems) == 8  # every item's screenshot is gone


# (reply, answer, value kind (None: YES/NO), strict, normalized, extracted)
REPLIES = [
    ("YES", "YES", None, True, True, "YES"),
    (" yes\n", "YES", None, True, True, "YES"),
    ("YES.", "YES", None, False, True, "YES"),  # upstream's rule fails it; ours reads the answer
    ("Yes, it is connected.", "YES", None, False, True, "YES"),
    ("The left edges line up.\nAnswer: **NO**", "NO", None, False, True, "NO"),
    ("No.\nThe block floats above the stack.", "NO", None, False, True, "NO"),
    ("I know which block it is.", "NO", None, False, False, None),  # "no" inside "know" is no answer
    ("<think>maybe yes</think>\nNO", "NO", None, False, True, "NO"),
    ("", "YES", None, False, False, None),
    ("-10", "-10", "number", True, True, "-10"),
    ("\u221210", "-10", "number", False, True, "-10"),  # a Unicode minus
    ("10.0", "10", "number", False, True, "10.0"),
    ("The field shows 15, so the answer is 15.", "15", "number", False, True, "15"),
    ("Answer: 12", "15", "number", False, False, "12"),
    ("`left arrow`", "left arrow", "dropdown", False, True, "left arrow"),
    ("Left Arrow.", "left arrow", "dropdown", False, True, "Left Arrow"),  # options case-insensitively
    ('"apple"', "apple", "text", False, True, "apple"),
    ("Apple", "apple", "text", False, False, "Apple"),  # text exactly
    ("The block's text is 'Hello!'.", "Hello!", "text", False, True, "Hello!"),
    ("Hello.", "Hello", "text", False, True, "Hello."),  # a sentence's closing period
]


@pytest.mark.parametrize(("reply", "answer", "value_kind", "strict", "normalized", "extracted"), REPLIES)
def test_both_scorings_of_hand_made_replies(
    reply: str, answer: str, value_kind: str | None, strict: bool, normalized: bool, extracted: str | None
) -> None:
    answer_format = "yes_no" if value_kind is None else "value"
    score = score_reply(reply, answer, answer_format, value_kind)  # type: ignore[arg-type]
    assert (score.strict, score.normalized, score.extracted) == (strict, normalized, extracted)
    assert score.strict == strict_correct(reply, answer, answer_format)  # type: ignore[arg-type]
    assert score.parse == ("no_answer" if not reply.strip() else "ok" if extracted is not None else "unparsed")


def test_a_hostile_reply_is_read_in_bounded_time() -> None:
    reply = "`" * 500_000 + "'" * 500_000 + "answer is " * 20_000 + "yes"
    assert score_reply(reply, "YES", "yes_no", None).normalized


def test_the_prompt_shows_the_question_and_screenshot_but_no_label() -> None:
    item = PerceptionItem.model_validate(
        {"id": "f-num", "kind": "field", "tag": "exact_match_numeric", "question": "What number is shown?",
         "answer_format": "value", "value_kind": "number", "answer": "-10", "screenshot": "x.png"}
    )  # fmt: skip
    image = png(200)
    messages = perception_messages(item.question, item.answer_format, item.value_kind, image)
    system, user = messages
    assert system["role"] == "system" and user["role"] == "user"
    text = next(part["text"] for part in user["content"] if part["type"] == "text")
    assert "What number is shown?" in text and "the number exactly" in text
    url = next(part["image_url"]["url"] for part in user["content"] if part["type"] == "image_url")
    assert base64.b64decode(url.removeprefix("data:image/png;base64,")) == image
    everything = json.dumps(messages)
    assert "-10" not in everything and "exact_match" not in everything
