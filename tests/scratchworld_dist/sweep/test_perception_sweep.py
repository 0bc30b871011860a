"""``benchmark: perception`` end to end: configs, the planned matrix and its ids, a sweep of the scripted agents
on Ray that resumes, and the llm agent against a real local OpenAI-compatible server (image parts checked,
failed calls recorded as errors with their class, never as wrong answers)."""

from __future__ import annotations

import base64
import json
import os
import re
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._run import plan_run
from scratchworld_dist.kinds.perception.items import load_perception_suite
from scratchworld_dist.results import RunStore
from scratchworld_dist.scheduling._admission import BROWSERLESS_PER_CORE, admitted_slots
from scratchworld_dist.sweep import load_sweep_config
from scratchworld_dist.viewer import ViewerSite, export_site
from tests.conftest import MODEL_KEY
from tests.support.openai_server import Behaviour, OpenAIServer, reply, status
from tests.support.perception_suites import ITEMS, write_suite
from tests.support.sweep_driver import run_here

SECRET = MODEL_KEY


@pytest.fixture
def suite(tmp_path: Path) -> Path:
    return write_suite(tmp_path / "suite")


def write(tmp_path: Path, suite: Path, **fields: Any) -> Path:
    config: dict[str, Any] = {
        "name": "perception-test",
        "benchmark": "perception",
        "suite": str(suite),
        "agent": "oracle",
        "output": str(tmp_path / "run"),
    }
    config.update(fields)
    path = tmp_path / "perception.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


LLM = {"api_base_env": "SCRATCHWORLD_LLM_BASE_URL", "api_key_env": "SCRATCHWORLD_LLM_API_KEY"}


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        (
            {"agent": "noop"},
            r"agent 'noop' is not registered for the perception benchmark \(registered: always_yes, llm, oracle\)",
        ),
        ({"agent": "jitter"}, "'jitter' is an agent of drag"),
        ({"perception": {"agents": ["oracle", {"name": "always_yes", "params": {"x": 1}}]}}, "takes no params"),
        ({"perception": {"agents": ["llm"]}}, "needs at least one entry under models"),
        ({"perception": {"kinds": ["colour"]}}, "perception.kinds.0"),
        ({"tasks": {"ids": ["no-such-item"]}}, "not in the suites: no-such-item"),
        ({"episodes": {"memory": {"kind": "online"}}}, "memory and synthetic are for task suites"),
        ({"memory": {"kind": "online"}}, "memory and synthetic are for task suites"),  # its former top-level key
    ],
)
def test_bad_perception_configs_are_one_line_naming_the_field(
    tmp_path: Path, suite: Path, fields: dict[str, Any], message: str
) -> None:
    with pytest.raises(ConfigError, match=message) as caught:
        plan_run(load_sweep_config(write(tmp_path, suite, **fields)))
    assert "\n" not in str(caught.value)


def test_the_matrix_is_agents_models_items_seeds_with_ids_that_follow_the_content(tmp_path: Path, suite: Path) -> None:
    models = [{"model": "openai/a", **LLM}, {"model": "openai/b", "temperature": 0, **LLM}]
    fields: dict[str, Any] = {"seeds": 2, "models": models, "perception": {"agents": ["oracle", "always_yes", "llm"]}}
    plan = plan_run(load_sweep_config(write(tmp_path, suite, **fields)))
    scripted, llm = 2 * 8 * 2, 2 * 8 * 2  # scripted agents once, without a model; llm once per model
    assert len(plan.jobs) == scripted + llm and len({job.job_id for job in plan.jobs}) == len(plan.jobs)
    assert {(job.category, job.body.item.kind) for job in plan.jobs} == {  # type: ignore[attr-defined]
        ("connection", "connection"),
        ("existence", "existence"),
        ("field", "field"),
    }
    assert not any(job.needs_browser for job in plan.jobs)
    limits = load_sweep_config(write(tmp_path, suite)).limits
    assert admitted_slots(limits, plan.jobs, "h", print) == BROWSERLESS_PER_CORE * (os.cpu_count() or 1)
    again = {job.job_id for job in plan_run(load_sweep_config(write(tmp_path, suite, **fields))).jobs}
    assert again == {job.job_id for job in plan.jobs}
    # A changed answer or screenshot is a new item: its jobs get new ids, the others keep theirs.
    lines = (suite / "items.jsonl").read_text().splitlines()
    lines[0] = json.dumps({**json.loads(lines[0]), "answer": "NO"})
    (suite / "items.jsonl").write_text("\n".join(lines) + "\n")
    changed = plan_run(load_sweep_config(write(tmp_path, suite, **fields))).jobs
    moved = {job.task_id for job in changed if job.job_id not in again}
    assert moved == {"c-yes"}
    shot = load_perception_suite(suite).item("e-no").screenshot  # one of three screenshots the items share
    shot.write_bytes(shot.read_bytes() + b"\x00")
    sharing = {i.id for i in load_perception_suite(suite).items if i.screenshot == shot}
    later = plan_run(load_sweep_config(write(tmp_path, suite, **fields))).jobs
    assert {job.task_id for job in later if job.job_id not in again} == sharing | {"c-yes"}
    kinds = plan_run(load_sweep_config(write(tmp_path, suite, perception={"kinds": ["field"]})))
    assert {job.task_id for job in kinds.jobs} == {"f-num", "f-drop", "f-text", "f-eq"}


@pytest.mark.ray
def test_the_scripted_agents_score_100_and_the_yes_share_and_the_run_resumes(
    tmp_path: Path, suite: Path, model_ray: int
) -> None:
    """(On the module's ``model_ray``, which the LLM test needs, rather than a second Ray.)"""
    config = write(
        tmp_path,
        suite,
        perception={"agents": ["oracle", "always_yes"], "optional_suites": [str(tmp_path / "not-here")]},
    )
    code, out = run_here(config)
    assert code == 0, out
    assert "not-here is not here; its items are skipped" in " ".join(out.split())
    report = (tmp_path / "run" / "report.md").read_text()  # the run prints, and keeps, the perception report
    assert report.startswith("# ScratchWorld perception report") and "## YES/NO confusion" in out
    store = RunStore(tmp_path / "run")
    rows = store.read_table("perception").to_pylist()
    jobs = store.read_table("jobs").to_pylist()
    assert len(rows) == len(jobs) == 16
    by_agent: dict[str, list[dict[str, Any]]] = {}
    for row in rows:
        by_agent.setdefault(row["agent"], []).append(row)
    assert all(row["strict_correct"] and row["normalized_correct"] for row in by_agent["oracle"])
    yes = [row["item_id"] for row in by_agent["always_yes"] if row["normalized_correct"]]
    assert sorted(yes) == sorted(item_id for item_id, *_, answer in ITEMS if answer == "YES")
    assert all(row["reply"] == "YES" for row in by_agent["always_yes"])
    outcomes = {(job["agent"], job["task_id"]): job["outcome"] for job in jobs}
    assert outcomes[("always_yes", "f-num")] == "failed" and outcomes[("oracle", "f-num")] == "passed"
    assert {job["editors_held"] for job in jobs} == {0}  # no worker opened an editor for a static screenshot
    # Three screenshots, stored once for the run's 16 jobs, where each row says.
    images = sorted((tmp_path / "run" / "images").iterdir())
    assert len(images) == 3
    assert {row["screenshot"] for row in rows} == {f"images/{path.name}" for path in images}
    assert not any((tmp_path / "run" / "artifacts").rglob("*.png"))
    code, out = run_here(config)
    assert code == 0, out
    assert "16 already decided, 0 to run" in " ".join(out.split())
    assert len(store.read_table("jobs").to_pylist()) == 16
    # The viewer shows a job's answer, both scores and the screenshot the run keeps once; an export copies it.
    site = ViewerSite([tmp_path / "run"])
    wrong = next(job for job in jobs if job["agent"] == "always_yes" and job["task_id"] == "f-num")
    page = site.get(f"runs/0/jobs/{wrong['job_id']}.html")
    assert page is not None and page.body is not None
    text = page.body.decode()
    assert "What number is shown in the numeric field" in text and "<code>-10</code>" in text
    assert 'normalized <span class="badge failed">wrong</span>' in text and "Final project" not in text
    (src,) = re.findall(r'<img loading="lazy" src="\.\./(images/[0-9a-f]{64}\.png)"', text)
    served = site.get(f"runs/0/{src}")
    kept = (tmp_path / "run" / src).read_bytes()
    assert served is not None and served.file is not None and served.file.read_bytes() == kept
    assert site.get("runs/0/images/../../manifest.json") is None and site.get("runs/0/images/x.png") is None
    export_site(site, tmp_path / "export")
    assert (tmp_path / "export" / "runs" / "0" / src).read_bytes() == kept


class ItemModel:
    """Answers each item from the question it is shown: right but wordy for model ``wordy``, right and terse for
    ``terse``; ``denied`` has no access (401) and ``flaky`` fails once with a 500 before it answers."""

    def __init__(self) -> None:
        self.answers = {question: answer for _, _, _, question, _, answer in ITEMS}
        self.failed_once: set[str] = set()

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        model = body["model"]
        if model == "denied":
            return status(401)
        text = next(part["text"] for part in body["messages"][-1]["content"] if part["type"] == "text")
        question = text.removeprefix("Question: ").split("\n\n")[0]
        answer = self.answers[question]
        if model == "flaky" and question not in self.failed_once:
            self.failed_once.add(question)
            return status(500)
        if model == "wordy":
            return reply(f"Looking at the code area closely.\nAnswer: {answer}.")
        return reply(answer)


@pytest.fixture
def server(model_server: OpenAIServer, model_ray: int) -> OpenAIServer:
    """The module's server answering as the item models; the module's Ray has it in its environment."""
    return model_server.reset(ItemModel())


@pytest.mark.ray
@pytest.mark.slow
def test_the_llm_agent_sees_each_screenshot_and_question_and_failed_calls_are_errors(
    tmp_path: Path, suite: Path, server: OpenAIServer
) -> None:
    config = write(
        tmp_path,
        suite,
        agent="llm",
        models=[{"model": f"openai/{name}", "name": name, **LLM} for name in ("terse", "wordy", "flaky", "denied")],
        llm={"retry": {"max_attempts": 2, "initial_backoff_s": 0.05}},
        limits={"retries": 1, "episode_timeout_s": 60},
        probe=False,  # the denied model's jobs are the point here (the probe: tests/.../scheduling/test_preflight.py)
    )
    code, log = run_here(config)
    assert code == 1, log  # the denied model's jobs remain errors
    store = RunStore(tmp_path / "run")
    jobs = store.read_table("jobs").to_pylist()
    rows = {(row["model"], row["item_id"]): row for row in store.read_table("perception").to_pylist()}
    denied = [job for job in jobs if job["model"] == "denied"]
    assert {(job["outcome"], job["error_class"], job["attempt"]) for job in denied} == {("error", "model_auth", 1)}
    assert len(denied) == 8 and not any(model == "denied" for model, _ in rows)  # no verdict: no perception row
    for item_id, *_, answer in ITEMS:
        terse, wordy, flaky = (rows[(model, item_id)] for model in ("terse", "wordy", "flaky"))
        assert terse["strict_correct"] and terse["normalized_correct"] and terse["reply"] == answer
        assert flaky["strict_correct"]  # the 500 was retried within the call
        assert not wordy["strict_correct"] and wordy["normalized_correct"]  # upstream's rule fails "Answer: YES."
        assert wordy["extracted"] is not None
    # Every request showed the item's own screenshot and question, and never its label.
    suite_items = {item.question: item for item in load_perception_suite(suite).items}
    asked = [request.body for request in server.requests if request.body["model"] != "denied"]
    assert len(asked) == 8 * 3 + 8  # three models answer every item; flaky once more per item
    for body in asked:
        user = body["messages"][-1]["content"]
        text = next(part["text"] for part in user if part["type"] == "text")
        item = suite_items[text.removeprefix("Question: ").split("\n\n")[0]]
        url = next(part["image_url"]["url"] for part in user if part["type"] == "image_url")
        assert url.startswith("data:image/png;base64,")
        assert base64.b64decode(url.split(",", 1)[1]) == item.screenshot.read_bytes()
        assert item.tag not in json.dumps(body["messages"])
    for path in (tmp_path / "run").rglob("*"):
        if path.is_file():
            assert SECRET.encode() not in path.read_bytes(), path
    assert SECRET not in log
