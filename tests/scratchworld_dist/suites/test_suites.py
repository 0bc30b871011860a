"""Both suite loaders behind load_suite, and every bad-input case they must name."""

from __future__ import annotations

import json
import shutil
from collections import Counter
from pathlib import Path

import pytest

from scratchworld_dist import SuiteError, TaskNotFoundError, load_suite
from scratchworld_dist.suites import UPSTREAM_TIMEOUT_S, find_golden
from tests.conftest import SUITE_DIR


@pytest.fixture
def native_copy(tmp_path: Path) -> Path:
    """A writable copy of our suite with two tasks."""
    root = tmp_path / "suite"
    root.mkdir()
    shutil.copy(SUITE_DIR / "suite.json", root)
    shutil.copy(SUITE_DIR / "harness.js", root)
    shutil.copytree(SUITE_DIR / "compute" / "sum_two_numbers", root / "compute" / "sum_two_numbers")
    shutil.copytree(SUITE_DIR / "compute" / "sum_two_numbers", root / "create" / "another_task")
    return root


# --- our own suite -----------------------------------------------------------------------


def test_our_suite_has_at_least_three_tasks_per_category() -> None:
    suite = load_suite(SUITE_DIR)
    assert suite.kind == "scratchworld_dist"
    counts = Counter(task.category for task in suite.tasks)
    assert all(counts[category] >= 3 for category in ("create", "debug", "extend", "compute")), counts
    for task in suite.tasks:
        assert task.golden_project is not None and task.golden_project.is_file()
        assert task.helper_script == SUITE_DIR / "harness.js"
        assert task.helper_global == "Harness"
        spec = task.evaluation_spec()
        assert "module.exports" in spec.script_source and spec.helper_source


def test_native_task_fields(native_copy: Path) -> None:
    suite = load_suite(native_copy)
    task = suite.task("sum_two_numbers")
    assert task.category == "compute"
    assert task.instruction.startswith("Complete the starter project")
    assert task.timeout_s == 40
    assert [t.id for t in suite.tasks] == ["another_task", "sum_two_numbers"]  # category order
    assert [t.id for t in suite.select(categories=["compute"])] == ["sum_two_numbers"]


def test_unknown_task_id_and_category(native_copy: Path) -> None:
    suite = load_suite(native_copy)
    with pytest.raises(TaskNotFoundError, match="no task 'nope'"):
        suite.select(ids=["nope"])
    with pytest.raises(SuiteError, match="unknown category 'games'"):
        suite.select(categories=["games"])


def _expect_problem(root: Path, path: Path, message: str) -> None:
    with pytest.raises(SuiteError) as caught:
        load_suite(root)
    assert str(path) in str(caught.value)
    assert message in str(caught.value)


def test_malformed_task_json_names_the_file(native_copy: Path) -> None:
    bad = native_copy / "create" / "another_task" / "task.json"
    bad.write_text('{"instruction": "x",')
    _expect_problem(native_copy, bad, "malformed JSON")


def test_unknown_key_in_task_json(native_copy: Path) -> None:
    bad = native_copy / "create" / "another_task" / "task.json"
    bad.write_text(json.dumps({"instruction": "x", "timeout": 5}))
    _expect_problem(native_copy, bad, "timeout: Extra inputs are not permitted")


def test_unknown_category_folder(native_copy: Path) -> None:
    shutil.copytree(native_copy / "create", native_copy / "games")
    _expect_problem(native_copy, native_copy / "games", "unknown category folder 'games'")


def test_missing_project_and_script_are_both_reported(native_copy: Path) -> None:
    task_dir = native_copy / "create" / "another_task"
    (task_dir / "initial.sb3").unlink()
    (task_dir / "evaluate.js").unlink()
    with pytest.raises(SuiteError) as caught:
        load_suite(native_copy)
    message = str(caught.value)
    assert "2 problems" in message
    assert f"{task_dir / 'initial.sb3'}: missing" in message
    assert f"{task_dir / 'evaluate.js'}: missing" in message


def test_bad_suite_file(native_copy: Path) -> None:
    (native_copy / "suite.json").write_text(json.dumps({"format": "other/9", "name": "x"}))
    _expect_problem(native_copy, native_copy / "suite.json", "format")


def test_missing_helper(native_copy: Path) -> None:
    (native_copy / "harness.js").unlink()
    _expect_problem(native_copy, native_copy / "suite.json", "helper 'harness.js' does not exist")


def test_not_a_suite(tmp_path: Path) -> None:
    with pytest.raises(SuiteError, match="not a task suite"):
        load_suite(tmp_path)
    with pytest.raises(SuiteError, match="no such directory"):
        load_suite(tmp_path / "absent")


# --- upstream clones ------------------------------------------------------------------------


def test_upstream_clone_loads_all_83_tasks(upstream_clone: Path) -> None:
    suite = load_suite(upstream_clone)
    assert suite.kind == "upstream"
    assert Counter(t.category for t in suite.tasks) == {"create": 20, "debug": 20, "extend": 18, "compute": 25}
    assert all(t.timeout_s == UPSTREAM_TIMEOUT_S for t in suite.tasks)
    assert all(t.golden_project is not None for t in suite.tasks)
    gcd = suite.task("calculate_gcd")
    assert gcd.initial_project.name == "calculate_gcd.sb3"
    assert gcd.golden_project is not None and gcd.golden_project.name == "calculate_gcd_golden.sb3"
    assert gcd.helper_script is not None and gcd.helper_script.name == "evaluation_utils.js"
    assert gcd.helper_global == "EvaluationUtils"


def test_upstream_debug_tasks_share_their_starter_golden(upstream_clone: Path) -> None:
    suite = load_suite(upstream_clone)
    goldens = {t.id: t.golden_project.name for t in suite.tasks if t.category == "debug" and t.golden_project}
    assert goldens["pong_starter_touching_red_error"] == "pong_starter_golden.sb3"
    assert goldens["math_game_false_negative_error"] == "math_game_golden.sb3"
    assert goldens["maze_starter_goal_detection_error"] == "maze_starter_golden.sb3"
    assert goldens["coordinate_reporter_broadcast_missing_error"] == "coordinate_reporter_golden.sb3"
    assert goldens["simple_circuit_switch_immediate_turn_off_error"] == "simple_circuit_golden.sb3"
    assert goldens["party_costume"] == "party_costume_golden.sb3"


def test_find_golden_uses_prefixes_only_for_debug(tmp_path: Path) -> None:
    (tmp_path / "game_golden.sb3").write_bytes(b"x")
    assert find_golden(tmp_path, "game_some_bug", "debug") == tmp_path / "game_golden.sb3"
    assert find_golden(tmp_path, "game_some_bug", "create") is None


def test_upstream_task_lists(upstream_clone: Path) -> None:
    assert [t.id for t in load_suite(upstream_clone, task_list="3_tasks").tasks] == [
        "ask_and_echo",
        "backdrop_cycler",
        "balloon_clicker",
    ]
    assert len(load_suite(upstream_clone, task_list="all_tasks").tasks) == 83
    # Pointing at the clone's tasks/ folder finds the clone.
    assert len(load_suite(upstream_clone / "tasks", task_list="15_tasks").tasks) == 15


def test_a_clone_reads_its_task_lists_and_gives_debug_tasks_their_starters_golden(fake_clone: Path) -> None:
    suite = load_suite(fake_clone)
    assert suite.kind == "upstream" and [t.id for t in suite.tasks] == [
        "say_hello",
        "sum_two_says_nothing_error",
        "sum_two",
    ]
    assert all(t.timeout_s == UPSTREAM_TIMEOUT_S for t in suite.tasks)
    debug = suite.task("sum_two_says_nothing_error")
    assert debug.golden_project is not None and debug.golden_project.name == "sum_two_golden.sb3"
    helper = suite.task("sum_two").helper_script
    assert (
        helper is not None
        and helper.name == "evaluation_utils.js"
        and suite.task("sum_two").helper_global == ("EvaluationUtils")
    )
    assert [t.id for t in load_suite(fake_clone, task_list="2_tasks").tasks] == ["say_hello", "sum_two"]
    assert len(load_suite(fake_clone / "tasks", task_list="all_tasks").tasks) == 3  # tasks/ finds the clone


def test_upstream_task_list_naming_a_missing_task(fake_clone: Path) -> None:
    listing = fake_clone / "tasks" / "mine.json"
    listing.write_text(json.dumps({"create": ["say_hello.json", "ghost.json"]}))
    _expect_problem_list(fake_clone, "mine", fake_clone / "tasks" / "create" / "ghost.json", "missing")
    listing.write_text(json.dumps({"games": ["say_hello.json"]}))
    _expect_problem_list(fake_clone, "mine", listing, "unknown category 'games'")


def _expect_problem_list(root: Path, task_list: str, path: Path, message: str) -> None:
    with pytest.raises(SuiteError) as caught:
        load_suite(root, task_list=task_list)
    assert str(path) in str(caught.value)
    assert message in str(caught.value)


def test_upstream_missing_script_names_the_expected_path(fake_clone: Path) -> None:
    script = fake_clone / "scratch-bench-api" / "api" / "evaluation_scripts" / "say_hello.js"
    script.unlink()
    _expect_problem(fake_clone, script, "evaluation script missing")


def test_upstream_missing_helper(fake_clone: Path) -> None:
    helper = fake_clone / "scratch-bench-api" / "api" / "evaluation_scripts" / "evaluation_utils.js"
    helper.unlink()
    _expect_problem(fake_clone, helper, "missing")


@pytest.mark.parametrize(
    ("content", "message"),
    [
        ("{broken", "malformed JSON"),
        ('{"type": "puzzle", "instruction": "x", "initial_project": "default.sb3"}', "unknown category 'puzzle'"),
        ('{"type": "debug", "instruction": "x", "initial_project": "default.sb3"}', "declares type 'debug'"),
        ('{"type": "create", "instruction": "x", "initial_project": "absent.sb3"}', "'absent.sb3' does not exist"),
        ('{"type": "create", "initial_project": "default.sb3"}', "instruction: Field required"),
    ],
)
def test_upstream_bad_task_files(fake_clone: Path, content: str, message: str) -> None:
    bad = fake_clone / "tasks" / "create" / "say_hello.json"
    bad.write_text(content)
    _expect_problem(fake_clone, bad, message)


def test_shared_data_reports_every_missing_script(upstream_dir: Path) -> None:
    """The shared data holds some tasks' scripts, not all: each task without one is a problem, named."""
    scripts = upstream_dir / "scratch-bench-api" / "api" / "evaluation_scripts"
    tasks = sorted((upstream_dir / "tasks").glob("*/*.json"))
    missing = [task.stem for task in tasks if not (scripts / f"{task.stem}.js").is_file()]
    if not missing:
        assert len(load_suite(upstream_dir).tasks) == len(tasks)
        return
    with pytest.raises(SuiteError) as caught:
        load_suite(upstream_dir)
    message = str(caught.value)
    assert f"{len(missing)} problems" in message or (len(missing) == 1 and "evaluation script missing" in message)
    assert message.count("evaluation script missing") == len(missing)
    assert all(name in message for name in missing)
