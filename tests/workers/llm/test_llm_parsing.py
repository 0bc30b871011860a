"""parse_reply on replies shaped like real GPT, Claude, Gemini and Qwen output, and repair_json on its own."""

from __future__ import annotations

import json

import pytest

from workers.llm import EXPECTED_FORMAT, ReplyParseError, parse_reply, repair_json

FENCE = "```"


def test_canonical_reply() -> None:
    action = '{"api": "add_block", "args": {"opcode": "motion_movesteps", "steps": 10}}'
    text = f"Analysis: The sprite needs a move block.\n{FENCE}json\n{action}\n{FENCE}"
    reply = parse_reply(text)
    assert reply.analysis == "The sprite needs a move block."
    assert reply.api == "add_block"
    assert reply.args == {"opcode": "motion_movesteps", "steps": 10}
    assert reply.request == {"api": "add_block", "args": {"opcode": "motion_movesteps", "steps": 10}}


def test_gpt_style_markdown_analysis_and_trailing_prose() -> None:
    text = (
        "**Analysis:** The green flag script is missing. I'll add the hat block first.\n\n"
        f'{FENCE}json\n{{\n  "api": "add_block",\n'
        f'  "args": {{"opcode": "event_whenflagclicked", "x": 100, "y": 80}}\n}}\n{FENCE}\n\n'
        "After this I will attach the loop."
    )
    reply = parse_reply(text)
    assert reply.api == "add_block"
    assert reply.args["opcode"] == "event_whenflagclicked"
    assert reply.analysis.startswith("The green flag script is missing.")
    assert reply.analysis.endswith("After this I will attach the loop.")


def test_claude_style_several_blocks_first_action_wins() -> None:
    text = (
        "Analysis: Looking at the current blocks:\n"
        f"{FENCE}\nwhen green flag clicked\n  forever\n{FENCE}\n"
        "The loop has no body. Earlier I considered this shape:\n"
        f'{FENCE}json\n{{"opcode": "control_forever"}}\n{FENCE}\n'
        "but the right action is:\n"
        f'{FENCE}json\n{{"api": "connect_blocks", "args": {{"parent": 3, "child": 5}}}}\n{FENCE}\n'
        f'{FENCE}json\n{{"api": "done"}}\n{FENCE}'
    )
    reply = parse_reply(text)
    assert (reply.api, reply.args) == ("connect_blocks", {"parent": 3, "child": 5})


def test_gemini_style_plain_fence_with_language_less_block() -> None:
    action = '{"api": "set_field", "args": {"block": 2, "field": "VALUE", "value": "0"}}'
    text = f"Analysis: Set the variable.\n\n{FENCE}\n{action}\n{FENCE}\n"
    assert parse_reply(text).args == {"block": 2, "field": "VALUE", "value": "0"}


def test_qwen_style_think_block_with_a_draft() -> None:
    text = (
        '<think>\nMaybe {"api": "click", "args": {"x": 1}}? No, the stage is hidden.\n</think>\n\n'
        f'Analysis: Show the stage first.\n{FENCE}json\n{{"api": "toggle_stage", "args": {{}}}}\n{FENCE}'
    )
    reply = parse_reply(text)
    assert reply.api == "toggle_stage"
    assert reply.analysis == "Show the stage first."


def test_think_block_is_used_when_the_answer_has_nothing() -> None:
    text = '<think>I will finish: {"api": "done"}</think>\nAll done.'
    assert parse_reply(text).api == "done"


def test_lone_closing_think_tag() -> None:
    text = 'reasoning {"api": "draft"} ...</think>Analysis: final.\n{"api": "final"}'
    assert parse_reply(text).api == "final"


def test_no_fence_first_balanced_object() -> None:
    text = 'Analysis: drag it. {"api": "drag", "args": {"from": [10, 20], "to": [300, 40]}} Then check.'
    reply = parse_reply(text)
    assert reply.args == {"from": [10, 20], "to": [300, 40]}
    assert reply.analysis == "drag it.\n\nThen check."


def test_braces_and_quotes_inside_strings() -> None:
    text = 'Analysis: type it.\n{"api": "type_text", "args": {"text": "say {hello} \\"world\\" it\'s }"}}'
    assert parse_reply(text).args == {"text": 'say {hello} "world" it\'s }'}


def test_prose_with_braces_before_the_action() -> None:
    text = 'The set {a, b} is empty, so: {"api": "done"}'
    assert parse_reply(text).api == "done"


def test_nested_action_object_is_found() -> None:
    text = '{"thought": "finish", "action": {"api": "done", "args": {}}}'
    assert parse_reply(text).api == "done"


@pytest.mark.parametrize(
    ("body", "args"),
    [
        ('{"api": "click", "args": {"x": 1, "y": 2,},}', {"x": 1, "y": 2}),  # trailing commas
        ("{'api': 'click', 'args': {'x': 1}}", {"x": 1}),  # single quotes
        ('{api: "click", args: {x: 1, label: "it\'s"}}', {"x": 1, "label": "it's"}),  # unquoted keys
        ('{"api": "set", "args": {"on": True, "off": False, "v": None}}', {"on": True, "off": False, "v": None}),
        ('{\n  "api": "click", // the button\n  "args": {"x": 1} /* centre */\n}', {"x": 1}),  # comments
        ('{\n  "api": "click",  # python comment\n  "args": {"x": 1}\n}', {"x": 1}),
        ('{\n  "api": "click"\n  "args": {"x": 1\n "y": 2}\n}', {"x": 1, "y": 2}),  # missing commas
        ('{"api": "type_text", "args": {"text": "line one\nline two"}}', {"text": "line one\nline two"}),  # raw newline
        ('{"api": "click", "args": {"x": 1}', {"x": 1}),  # closing brace missing (output cut after the value)
        ('{"api": "scroll", "args": {"dy": -.5, "n": +3}}', {"dy": -0.5, "n": 3}),
        ("{'api': 'say', 'args': {'text': 'He said \\'hi\\''}}", {"text": "He said 'hi'"}),
    ],
)
def test_repairs_common_json_mistakes(body: str, args: dict[str, object]) -> None:
    reply = parse_reply(f"Analysis: act.\n{FENCE}json\n{body}\n{FENCE}")
    assert reply.args == args


def test_args_missing_or_null_become_empty() -> None:
    assert parse_reply('{"api": "done"}').args == {}
    assert parse_reply('{"api": "done", "args": null}').request == {"api": "done", "args": {}}


def test_extra_keys_are_kept_and_api_is_trimmed() -> None:
    reply = parse_reply('{"api": " click ", "args": {}, "reason": "test"}')
    assert reply.request == {"api": "click", "args": {}, "reason": "test"}


def test_unclosed_fence() -> None:
    text = f'Analysis: done.\n{FENCE}json\n{{"api": "done", "args": {{}}}}'
    assert parse_reply(text).api == "done"


def test_inline_fence() -> None:
    assert parse_reply(f'{FENCE}json {{"api": "done"}}{FENCE}').api == "done"


def test_unicode_is_kept() -> None:
    assert parse_reply('{"api": "type_text", "args": {"text": "héllo \\u00e9 ✓"}}').args == {"text": "héllo é ✓"}


# -- replies that must fail, with feedback the model can act on -------------------------------------------------


def failure(text: str) -> ReplyParseError:
    with pytest.raises(ReplyParseError) as caught:
        parse_reply(text)
    assert EXPECTED_FORMAT in str(caught.value)
    return caught.value


def test_no_json_at_all() -> None:
    error = failure("Analysis: I think the task is complete now.")
    assert error.reason == "no_json"
    assert "no JSON action" in str(error)


def test_empty_reply() -> None:
    assert failure("").reason == "no_json"


def test_object_without_api() -> None:
    error = failure(f'Analysis: x\n{FENCE}json\n{{"action": "click", "args": {{"x": 1}}}}\n{FENCE}')
    assert error.reason == "missing_api"
    assert '"api"' in str(error)


@pytest.mark.parametrize("api", ["5", "null", '["click"]', '""', '{"name": "click"}'])
def test_api_not_a_string(api: str) -> None:
    error = failure(f'{{"api": {api}, "args": {{}}}}')
    assert error.reason == "bad_api"
    assert "must be a non-empty string" in str(error)


def test_args_not_an_object() -> None:
    error = failure('{"api": "click", "args": [10, 20]}')
    assert error.reason == "bad_args"
    assert "[10, 20]" in str(error)


def test_hopeless_json_reports_the_parser_error() -> None:
    error = failure(f'Analysis: x\n{FENCE}json\n{{"api": "click", "args": {{"x": 1 @ 2}}}}\n{FENCE}')
    assert error.reason == "invalid_json"
    assert "line 1 column" in str(error)


def test_truncated_string_is_refused_not_guessed() -> None:
    error = failure(f'Analysis: typing.\n{FENCE}json\n{{"api": "type_text", "args": {{"text": "Hello, wor')
    assert error.reason == "invalid_json"


def test_prose_only_braces() -> None:
    assert failure("Use the {variable} block inside {the loop}.").reason == "no_json"


def test_a_bare_list_is_not_an_action() -> None:
    assert failure(f'{FENCE}json\n[{{"x": 1}}]\n{FENCE}').reason == "missing_api"


# -- repair_json itself ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("text", "value"),
    [
        ('{"a": 1}', {"a": 1}),
        ("{'a': [1, 2,], 'b': None,}", {"a": [1, 2], "b": None}),
        ("{a: {b: [true, False]}} trailing prose: it's fine", {"a": {"b": [True, False]}}),
        ('{"a": "x" "b": "y"}', {"a": "x", "b": "y"}),
        ('{"a": [1 2 3]}', {"a": [1, 2, 3]}),
        ('{"a": 1,, "b": 2}', {"a": 1, "b": 2}),
        ('{"a": {"b": [1, {"c": 2', {"a": {"b": [1, {"c": 2}]}}),
        ('{"s": "tab\\tq\\"\\/"}', {"s": 'tab\tq"/'}),
        ('{"k": 1e3, "m": -2.5E-1}', {"k": 1000.0, "m": -0.25}),
    ],
)
def test_repair_json(text: str, value: object) -> None:
    assert json.loads(repair_json(text)) == value


@pytest.mark.parametrize("text", ['{"a": 1]', '{"a": "open', "{'a': 1 @}"])
def test_repair_json_refuses(text: str) -> None:
    with pytest.raises(ValueError, match=r"\w"):
        repair_json(text)
