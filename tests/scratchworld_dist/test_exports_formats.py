"""``scratchworld export``: a leaderboard that a recomputation from the Parquet (DuckDB, effective attempts by
SQL) agrees with, upstream's submission lines of executed actions, and ATIF trajectories that validate against
the published schema and the format's own rules."""

from __future__ import annotations

import json
from datetime import UTC, datetime
from pathlib import Path

import duckdb
import jsonschema
import pytest
from atif import Trajectory
from pydantic import ValidationError

from scratchworld_dist.kinds.tasks.exports import reasoning_of, wilson_interval
from scratchworld_dist.results import JobRecord, RunStore, StepRow
from tests.conftest import REPO
from tests.support.cli_runner import invoke
from tests.support.run_dirs import drag_record, job, make_run
from workers.contract import StepObservation, StepRecord

ROWS = [  # (job, attempt, outcome, model, mode, tests passed, cost)
    ("a1", 1, "error", "gpt", "composite", 0, 0.01),
    ("a1", 2, "passed", "gpt", "composite", 2, 0.02),
    ("a2", 1, "failed", "gpt", "composite", 1, 0.03),
    ("a3", 1, "passed", "gpt", "composite", 2, 0.04),
    ("a3", 2, "error", "gpt", "composite", 0, 0.05),  # a later error does not undo a verdict
    ("b1", 1, "passed", "claude", "composite", 2, 0.10),
    ("b2", 1, "error", "claude", "composite", 0, 0.20),  # no verdict: out of SR
    ("c1", 1, "failed", "gpt", "primitive", 0, 0.30),
]


def step_rows(job_id: str, attempt: int) -> list[StepRow]:
    actions = [("add_block", {"blockType": "event_whenflagclicked"}), ("done", {})]
    return [
        StepRow(
            job_id=job_id, attempt=attempt, step=index, action=action, args_json=json.dumps(args), ok=True,
            error_code=None, error_message=None, latency_s=0.1, observation_s=0.0, warnings=None, llm_calls=1,
            input_tokens=50, output_tokens=5, cost_usd=0.001, llm_cache_hits=None,
        )
        for index, (action, args) in enumerate(actions)
    ]  # fmt: skip


@pytest.fixture
def run(tmp_path: Path) -> Path:
    run_dir = tmp_path / "run"
    store = RunStore(run_dir)  # one attempt keeps its whole trajectory: it wins over its steps rows
    store.open_for_writing()
    kept = StepRecord(index=0, action="click", args={"x": 10, "y": 20}, ok=True, reply="I click the flag")
    folder = store.write_artifact("b1", 1, "trajectory.jsonl", kept.model_dump_json().encode() + b"\n")
    store.close()
    records = []
    for job_id, attempt, outcome, model, mode, passed, cost in ROWS:
        decided = outcome != "error"
        row = job(
            job_id, outcome, attempt=attempt, model=model, litellm_model=f"openai/{model}", mode=mode,
            task_id=f"task-{job_id}", tests_passed=passed, tests_total=2 if decided else 0,
            psr=passed / 2 if decided else None, cost_usd=cost, artifact_dir=folder if job_id == "b1" else None,
        )  # fmt: skip
        records.append(JobRecord(job=row, steps=step_rows(job_id, attempt)))
    return make_run(run_dir, records, planned=6, tasks=6)


def sql_leaderboard(run_dir: Path) -> dict[tuple[str, str], tuple[int, int]]:
    """(model, mode) -> (passed, determinate) over effective attempts, computed by DuckDB from the shards."""
    query = f"""
        with ranked as (
            select *, row_number() over (
                partition by job_id order by (outcome <> 'error') desc, attempt desc) as rank
            from read_parquet('{run_dir}/jobs/*.parquet'))
        select model, mode, count(*) filter (where outcome = 'passed'), count(*) filter (where outcome <> 'error')
        from ranked where rank = 1 group by model, mode"""
    return {(m, mode): (p, d) for m, mode, p, d in duckdb.sql(query).fetchall()}


def test_the_leaderboard_agrees_with_a_recomputation_from_the_parquet(run: Path, tmp_path: Path) -> None:
    done = invoke("export", str(run), "--format", "leaderboard", "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    entries = json.loads((tmp_path / "out" / "leaderboard.json").read_text())["entries"]
    assert {(e["model"], e["mode"]): (e["passed"], e["determinate"]) for e in entries} == sql_leaderboard(run)
    for entry in entries:
        low, high = wilson_interval(entry["passed"], entry["determinate"])
        assert entry["sr"] == pytest.approx(entry["passed"] / entry["determinate"])
        assert (entry["sr_low"], entry["sr_high"]) == (pytest.approx(low), pytest.approx(high))
        assert entry["sr_low"] <= entry["sr"] <= entry["sr_high"]
    assert [(e["rank"], e["model"], e["mode"]) for e in entries] == [
        (1, "claude", "composite"),
        (2, "gpt", "composite"),
        (1, "gpt", "primitive"),
    ]  # fmt: skip: one ranking per mode
    csv_lines = (tmp_path / "out" / "leaderboard.csv").read_text().splitlines()
    assert csv_lines[0].startswith("rank,label,agent,model,mode") and len(csv_lines) == 4


def test_tied_entries_share_a_rank_and_the_next_counts_them(tmp_path: Path) -> None:
    rows = [  # model: the jobs' outcomes; "a" and "b" tie on SR, PSR and cost per success
        ("a", ["passed", "failed"]), ("b", ["failed", "passed"]),
        ("c", ["failed", "failed"]), ("d", ["passed", "passed"]),
    ]  # fmt: skip
    jobs = [
        job(f"{model}{i}", outcome, model=model, litellm_model=f"openai/{model}", task_id=f"t{i}", cost_usd=0.01,
            tests_passed=2 if outcome == "passed" else 0, tests_total=2, psr=1.0 if outcome == "passed" else 0.0)
        for model, outcomes in rows for i, outcome in enumerate(outcomes)
    ]  # fmt: skip
    run = make_run(tmp_path / "run", jobs, planned=8, tasks=2)
    done = invoke("export", str(run), "--format", "leaderboard", "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    entries = json.loads((tmp_path / "out" / "leaderboard.json").read_text())["entries"]
    ranks = sorted((e["rank"], e["model"]) for e in entries)
    assert ranks == [(1, "d"), (2, "a"), (2, "b"), (4, "c")]


def test_the_submission_has_one_line_per_task_with_the_executed_actions(run: Path, tmp_path: Path) -> None:
    done = invoke("export", str(run), "--format", "upstream-submission", "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    files = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert files == [
        "openai_claude_composite_llm_seed0.jsonl", "openai_gpt_composite_llm_seed0.jsonl",
        "openai_gpt_primitive_llm_seed0.jsonl",
    ]  # fmt: skip
    lines = [json.loads(line) for line in (tmp_path / "out" / files[1]).read_text().splitlines()]
    assert [line["take"] for line in lines] == ["task-a1", "task-a2", "task-a3"]
    assert set(lines[0]) == {"take", "type", "mode", "interactions", "source_interaction_log", "source_task_dir"}
    assert lines[0]["interactions"] == [
        {"turn": 1, "action": {"api": "add_block", "args": {"blockType": "event_whenflagclicked"}}},
        {"turn": 2, "action": {"api": "done", "args": {}}},
    ]
    claude = [json.loads(line) for line in (tmp_path / "out" / files[0]).read_text().splitlines()]
    assert [line["take"] for line in claude] == ["task-b1", "task-b2"]  # errors too, as upstream's script does
    claude = claude[0]
    assert claude["interactions"] == [{"turn": 1, "action": {"api": "click", "args": {"x": 10, "y": 20}}}]
    assert claude["source_interaction_log"].endswith("trajectory.jsonl")


def test_atif_trajectories_validate_against_the_atif_package_and_its_published_schema(
    run: Path, tmp_path: Path
) -> None:
    done = invoke("export", str(run), "--format", "atif", "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    schema = json.loads((REPO / "docs" / "schemas" / "atif-v1.8.schema.json").read_text())
    files = sorted((tmp_path / "out").rglob("*.json"))
    assert len(files) == 6  # one per job, at its counted attempt
    for path in files:
        data = json.loads(path.read_text())
        jsonschema.validate(data, schema)
        trajectory = Trajectory.model_validate(data)  # the atif package's models and rules
        assert trajectory.schema_version == "ATIF-v1.8" and trajectory.steps[0].source == "user"
        assert trajectory.final_metrics is not None and trajectory.final_metrics.total_steps == len(trajectory.steps)
        assert path.name.startswith(data["extra"]["task_id"] + "-")  # the task in the file name
        assert data["extra"]["suite"] == {"name": "ours", "kind": "native", "hash": "suite1"}
    a1 = json.loads((tmp_path / "out" / "sweep" / "task-a1-composite-seed0-a1-2.json").read_text())
    assert [s["tool_calls"][0]["function_name"] for s in a1["steps"][1:]] == ["add_block", "done"]
    assert a1["final_metrics"]["extra"]["outcome"] == "passed" and a1["agent"]["model_name"] == "openai/gpt"
    b1 = json.loads((tmp_path / "out" / "sweep" / "task-b1-composite-seed0-b1-1.json").read_text())
    assert b1["steps"][1]["message"] == "I click the flag"  # the reply, kept in the trajectory artifact


SYSTEM = "You edit a Scratch 3 project. # Task: make the cat say hello."
SHOT = "ab" * 32
BLOCKS = "## Blocks\n#1 event_whenflagclicked"
SHOWN = [{"type": "text", "text": "Result: ok"}, {"type": "image_ref", "sha256": SHOT}]


def test_an_atif_trajectory_holds_what_the_model_saw_said_and_thought(tmp_path: Path) -> None:
    first = StepRecord(
        index=0, action="add_block", args={"blockType": "looks_say"}, ok=True, data={"index": 3}, latency_s=2.0,
        llm_calls=1, input_tokens=100, output_tokens=20, cost_usd=0.002,
        prompt=[{"role": "system", "content": SYSTEM}, {"role": "user", "content": BLOCKS}],
        reply='<think>The cat needs a say block.</think>Analysis: add say.\n```json\n{"api": "add_block"}\n```',
        observation=StepObservation(text=BLOCKS),
    )  # fmt: skip
    second = StepRecord(
        index=1, action="click", args={"x": 5, "y": 6}, ok=False, error_code="OFF_PAGE", error_message="no",
        latency_s=1.5, llm_calls=1, input_tokens=120, output_tokens=10, cost_usd=0.003,
        prompt=[{"role": "user", "content": SHOWN}],
        reply="Analysis: click the flag.\n```json\n{}\n```",
    )  # fmt: skip
    store = RunStore(tmp_path / "run")
    store.open_for_writing()
    lines = b"".join(step.model_dump_json().encode() + b"\n" for step in (first, second))
    folder = store.write_artifact("j1", 1, "trajectory.jsonl", lines)
    store.close()
    (tmp_path / "run" / folder / "images").mkdir()
    (tmp_path / "run" / folder / "images" / f"{SHOT}.png").write_bytes(b"\x89PNG fake")
    started = datetime(2026, 1, 2, 3, 4, 5, tzinfo=UTC)
    row = job("j1", task_id="say_hello", artifact_dir=folder, started_at=started, setup_s=1.0, steps=2)
    config = {"agent": "llm", "models": [{"model": "gpt"}], "episodes": {"episode_clock": {"mode": "virtual"}}}
    oracle = job("j2", agent="oracle", task_id="say_hello", started_at=started, setup_s=1.0, llm_calls=0)
    no_llm = [StepRow(
        job_id="j2", attempt=1, step=0, action="done", args_json="{}", ok=True, error_code=None, error_message=None,
        latency_s=0.1, observation_s=0.0, warnings=None, llm_calls=0, input_tokens=0, output_tokens=0, cost_usd=0.0,
        llm_cache_hits=None,
    )]  # fmt: skip
    run = make_run(tmp_path / "run", [JobRecord(job=row), JobRecord(job=oracle, steps=no_llm)], planned=2, tasks=1,
                   config=config)  # fmt: skip
    done = invoke("export", str(run), "--format", "atif", "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    out = tmp_path / "out" / "sweep"
    data = json.loads((out / "say_hello-composite-seed0-j1-1.json").read_text())
    Trajectory.model_validate(data)
    steps = data["steps"]
    assert [s["source"] for s in steps] == ["system", "user", "agent", "user", "agent"]
    assert steps[0]["message"] == SYSTEM and steps[1]["message"] == BLOCKS
    assert steps[2]["reasoning_content"] == "The cat needs a say block."  # the think trace first
    assert steps[4]["reasoning_content"] == "click the flag."  # else the Analysis text
    assert steps[3]["message"] == [
        {"type": "text", "text": "Result: ok"},
        {"type": "image", "source": {"media_type": "image/png", "path": f"images/{SHOT}.png"}},
    ]
    assert (out / "images" / f"{SHOT}.png").read_bytes() == b"\x89PNG fake"  # the file the trajectory names
    assert [s["timestamp"] for s in steps] == [
        "2026-01-02T03:04:06.000Z",
        "2026-01-02T03:04:06.000Z",
        "2026-01-02T03:04:06.000Z",
        "2026-01-02T03:04:08.000Z",
        "2026-01-02T03:04:08.000Z",
    ]  # fmt: skip: start + setup, then + the first step's latency
    assert [steps[i]["extra"]["episode_clock_ms"] for i in (2, 4)] == [1000, 1000 + 50 + 500]
    assert json.loads(steps[4]["observation"]["results"][0]["content"]) == {
        "ok": False, "error": "OFF_PAGE", "message": "no"
    }  # fmt: skip
    assert steps[2]["metrics"] == {"prompt_tokens": 100, "completion_tokens": 20, "cost_usd": 0.002}
    oracle_steps = json.loads((out / "say_hello-composite-seed0-j2-1.json").read_text())["steps"]
    assert [s["source"] for s in oracle_steps] == ["user", "agent"]  # the instruction, then its one action
    assert oracle_steps[1]["llm_call_count"] == 0 and "metrics" not in oracle_steps[1]


def test_the_atif_package_enforces_the_format_s_rules() -> None:
    agent = {"name": "a", "version": "1"}
    user = {"step_id": 1, "source": "user", "message": "x"}
    gap = {
        "schema_version": "ATIF-v1.8",
        "agent": agent,
        "steps": [user, {"step_id": 3, "source": "agent", "message": ""}],
    }
    with pytest.raises(ValidationError, match="is not sequential"):
        Trajectory.model_validate(gap)
    user_metrics = {**user, "metrics": {"prompt_tokens": 1}}
    with pytest.raises(ValidationError, match="only valid on `source='agent'`"):
        Trajectory.model_validate({"schema_version": "ATIF-v1.8", "agent": agent, "steps": [user_metrics]})


def test_the_virtual_clock_s_lead_before_an_action_is_the_worker_s() -> None:
    from scratchworld_dist.kinds.tasks.exports._atif import ACTION_LEAD_MS
    from workers.kinds.tasks._pace import ACTION_LEAD_MS as WORKER_LEAD_MS

    assert ACTION_LEAD_MS == WORKER_LEAD_MS


def test_an_atif_trajectory_takes_the_clock_and_reasoning_the_worker_recorded(tmp_path: Path) -> None:
    """Steps recorded with their start, the page's time and the provider's reasoning are exported as recorded."""
    began = datetime(2026, 1, 2, 3, 4, 7, 250_000, tzinfo=UTC).timestamp()
    steps = [
        StepRecord(
            index=k, action="add_block", ok=True, latency_s=1.0, llm_calls=1, started_at=began + 3 * k,
            episode_clock_ms=1000 + 800 * k, reasoning="the provider's reasoning" if k == 0 else None,
            prompt=[{"role": "user", "content": BLOCKS}], reply="Analysis: add.\n```json\n{}\n```",
        )
        for k in range(2)
    ]  # fmt: skip
    store = RunStore(tmp_path / "run")
    store.open_for_writing()
    folder = store.write_artifact(
        "j1", 1, "trajectory.jsonl", b"".join(s.model_dump_json().encode() + b"\n" for s in steps)
    )
    store.close()
    started = datetime(2026, 1, 2, 3, 4, 5, tzinfo=UTC)
    row = job("j1", task_id="say_hello", artifact_dir=folder, started_at=started, setup_s=1.0, steps=2)
    config = {"agent": "llm", "models": [{"model": "gpt"}], "episodes": {"episode_clock": {"mode": "virtual"}}}
    tags = {"team": "vision", "budget": "small"}
    run = make_run(tmp_path / "run", [JobRecord(job=row)], planned=1, tasks=1, config=config, tags=tags)
    done = invoke("export", str(run), "--format", "atif", "--out", str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    data = json.loads((tmp_path / "out" / "sweep" / "say_hello-composite-seed0-j1-1.json").read_text())
    agent = [s for s in data["steps"] if s["source"] == "agent"]
    assert [s["timestamp"] for s in agent] == ["2026-01-02T03:04:07.250Z", "2026-01-02T03:04:10.250Z"]
    assert [s["extra"]["episode_clock_ms"] for s in agent] == [1000, 1800]  # as recorded, not computed
    assert agent[0]["reasoning_content"] == "the provider's reasoning"  # before the reply's own Analysis
    assert agent[1]["reasoning_content"] == "add."
    assert data["extra"]["timestamps"] == "wall clock: when the worker began each step"
    assert data["extra"]["tags"] == tags  # the run's --tag labels


def test_reasoning_is_read_from_a_think_trace_or_the_analysis() -> None:
    assert reasoning_of("<think> a </think><think>b</think>Analysis: c") == "a\n\nb"
    assert reasoning_of("Analysis: c\n```json\n{}\n```") == "c"
    assert reasoning_of('{"api": "done"}') is None and reasoning_of(None) is None


def test_runs_of_another_kind_are_refused_in_one_line(tmp_path: Path) -> None:
    drag = make_run(tmp_path / "drag", [drag_record("t1", 0, "passed")], planned=1, tasks=1)
    done = invoke("export", str(drag), "--format", "atif", "--out", str(tmp_path / "out"))
    assert done.returncode != 0 and "holds single-step drag jobs; export writes task-episode runs" in done.stderr
