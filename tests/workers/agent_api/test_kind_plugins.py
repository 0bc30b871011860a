"""Plugin agents of the drag and perception benchmarks: registered by entry point, run in real sweeps.

The two plugins are defined here and registered by a distribution's metadata written into a folder put on
the path (``scratchworld.drag_agents``, ``scratchworld.perception_agents``) before the module's Ray starts,
so the driver and its workers find them by name as they would an installed package's. Neither is shown the
answer (only the harness's own scripted agents are), and their code is part of their jobs' identity.
"""

from __future__ import annotations

import asyncio
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import yaml
from pydantic import BaseModel, ConfigDict

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._run import plan_run
from scratchworld_dist.results import RunStore
from scratchworld_dist.sweep import load_sweep_config, worker_job
from tests.conftest import REPO
from tests.support.perception_suites import ITEMS, write_suite
from tests.support.sweep_driver import run_here
from workers.agent_api import (
    DragAgentBase,
    DragAnswer,
    DragQuestion,
    ModelSource,
    PerceptionAgentBase,
    PerceptionQuestion,
    agent_class,
    agent_code,
    registered_agents,
)
from workers.contract import AgentUnavailableError, ModelSpec

ENTRY_POINTS = f"""\
[scratchworld.drag_agents]
nudge = {__name__}:NudgeDragAgent

[scratchworld.perception_agents]
always = {__name__}:AlwaysAgent
"""


class NudgeParams(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    dx: float = 30.0


class NudgeDragAgent(DragAgentBase):
    """Presses where ``gt_start`` marks the block and drops it ``dx`` px to the right."""

    Params = NudgeParams

    async def answer(self, question: DragQuestion, model: ModelSpec | None, models: ModelSource) -> DragAnswer:
        if question.regions is not None:
            raise AgentUnavailableError("a plugin was shown the regions")
        if question.gt_start is None:
            return DragAnswer(parse="no_answer", detail="no marked start")
        x, y = question.gt_start
        return DragAnswer(parse="ok", start=(float(x), float(y)), end=(x + self.params.dx, float(y)))  # type: ignore[attr-defined]


class AnswerParams(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)

    answer: str = "NO"


class AlwaysAgent(PerceptionAgentBase):
    """Answers ``params.answer`` to every item."""

    Params = AnswerParams

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: ModelSource) -> str:
        if question.label is not None:
            raise AgentUnavailableError("a plugin was shown the label")
        return str(self.params.answer)  # type: ignore[attr-defined]


class PeekingAgent(PerceptionAgentBase):
    """A plugin that claims the harness's privilege of seeing the answer."""

    privileged = True

    async def answer(self, question: PerceptionQuestion, model: ModelSpec | None, models: ModelSource) -> str:
        return question.label or ""


@pytest.fixture(scope="module")
def plugins(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """A folder holding the plugins' distribution metadata, on the path of this process and its workers."""
    site = tmp_path_factory.mktemp("kind-plugins")
    info = site / "kind_plugins-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: kind-plugins\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(ENTRY_POINTS)
    with pytest.MonkeyPatch.context() as patch:
        patch.syspath_prepend(str(site))
        patch.setenv("PYTHONPATH", f"{site}:{REPO}")
        yield site


@pytest.fixture(scope="module")
def plugin_ray(plugins: Path) -> Iterator[int]:
    """The module's Ray, started once the plugins are on the path its workers inherit."""
    from scratchworld_dist.scheduling import ray_runtime

    with ray_runtime(None, None) as slots:
        yield slots


def perception_config(tmp_path: Path, **fields: Any) -> Path:
    suite = tmp_path / "suite"
    if not suite.exists():
        write_suite(suite)
    body: dict[str, Any] = {
        "name": "perception-plugin",
        "benchmark": "perception",
        "suite": str(suite),
        "agent": "oracle",
        "output": str(tmp_path / "run"),
        **fields,
    }
    path = tmp_path / "perception.yaml"
    path.write_text(yaml.safe_dump(body))
    return path


def drag_config(tmp_path: Path, **fields: Any) -> Path:
    body: dict[str, Any] = {
        "name": "drag-plugin",
        "benchmark": "drag",
        "suite": str(REPO / "drag-tasks"),
        "agent": "oracle",
        "output": str(tmp_path / "run"),
        **fields,
    }
    path = tmp_path / "drag.yaml"
    path.write_text(yaml.safe_dump(body))
    return path


@pytest.mark.usefixtures("plugins")
def test_each_kind_lists_its_own_agents_and_plugins_join_theirs() -> None:
    assert {"oracle", "jitter", "llm", "nudge"} <= set(registered_agents("drag"))
    assert {"oracle", "always_yes", "llm", "always"} <= set(registered_agents("perception"))
    assert not {"jitter", "nudge", "always"} & set(registered_agents("tasks"))
    assert agent_class("nudge", "drag") is agent_class(f"{__name__}:NudgeDragAgent", "drag") is NudgeDragAgent
    assert agent_code(NudgeDragAgent) is not None and agent_code(agent_class("jitter", "drag")) is None
    assert agent_class("jitter", "drag").Params().model_dump() == {"sigma_px": 8.0}  # its params are its own
    assert agent_class("llm", "drag").needs_model and not agent_class("oracle", "perception").needs_model


@pytest.mark.usefixtures("plugins")
@pytest.mark.parametrize(
    ("benchmark", "fields", "fragment"),
    [
        ("perception", {"agent": f"{__name__}:NudgeDragAgent"}, "NudgeDragAgent serves drag, not perception"),
        ("perception", {"perception": {"agents": ["oracle", "nudge"]}}, "'nudge' is an agent of drag"),
        ("drag", {"agent": f"{__name__}:AlwaysAgent"}, "serves perception, not drag"),
        ("tasks", {"agent": f"{__name__}:AlwaysAgent"}, "serves perception, not tasks"),
        (
            "drag",
            {"agent": {"name": "nudge", "params": {"dy": 1}}},
            "agent nudge rejects its params: unknown dy (accepted: dx)",
        ),
        (
            "perception",
            {"agent": {"name": "always", "params": {"answer": 3}}},
            "agent always rejects its params: answer",
        ),
        ("perception", {"agent": f"{__name__}:PeekingAgent"}, "declares privileged = True, which would show it"),
    ],
)
def test_an_agent_of_another_kind_or_with_bad_params_is_refused_in_one_line(
    tmp_path: Path, benchmark: str, fields: dict[str, Any], fragment: str
) -> None:
    write = perception_config if benchmark == "perception" else drag_config
    if benchmark == "tasks":
        path = tmp_path / "tasks.yaml"
        path.write_text(yaml.safe_dump({"suite": str(REPO / "tasks"), "output": str(tmp_path / "run"), **fields}))
    else:
        path = write(tmp_path, **fields)
    with pytest.raises(ConfigError) as caught:
        load_sweep_config(path)
    message = str(caught.value)
    assert fragment in message and "\n" not in message, message


@pytest.mark.usefixtures("plugins")
def test_a_plugins_code_and_params_name_its_jobs_and_built_in_ids_stay(tmp_path: Path) -> None:
    def ids(*agents: Any) -> dict[str, set[str]]:
        plan = plan_run(load_sweep_config(perception_config(tmp_path, perception={"agents": list(agents)})))
        found: dict[str, set[str]] = {}
        for job in plan.jobs:
            found.setdefault(job.agent.display, set()).add(job.job_id)
            assert (job.agent_code is None) == (job.agent.name == "oracle")
        return found

    plain = ids("oracle", "always")
    assert ids("oracle", {"name": "always", "label": "relabelled"})["relabelled"] == plain["always"]
    assert ids({"name": "always", "params": {"answer": "YES"}})["always"].isdisjoint(plain["always"])
    module = Path(__file__)
    original = module.read_text()
    try:  # the plugin's code changes: so do its jobs, and the oracle's stay
        module.write_text(original + "\n# a local change\n")
        edited = ids("oracle", "always")
    finally:
        module.write_text(original)
    assert edited["oracle"] == plain["oracle"] and edited["always"].isdisjoint(plain["always"])


@pytest.mark.usefixtures("plugins")
def test_a_worker_with_other_plugin_code_refuses_the_job(tmp_path: Path) -> None:
    from workers.kinds.perception._runner import run_perception

    plan = plan_run(load_sweep_config(perception_config(tmp_path, agent="always")))
    job = plan.jobs[0]
    content = next(c for c in plan.contents if c.task.id == job.task_id)
    planned = worker_job(job, 1, 30)
    ran = asyncio.run(run_perception(planned, content.payload))  # type: ignore[arg-type]
    assert ran.outcome in ("passed", "failed")
    other = planned.model_copy(update={"agent_code": "0" * 16})
    refused = asyncio.run(run_perception(other, content.payload))  # type: ignore[arg-type]
    assert refused.outcome == "error" and refused.error_class == "harness_mismatch"
    assert f"the job was planned for {'0' * 16}: install the same version here" in (refused.error_message or "")


@pytest.mark.ray
def test_a_perception_plugin_runs_in_a_sweep_unshown_the_labels_and_resumes(tmp_path: Path, plugin_ray: int) -> None:
    config = perception_config(tmp_path, perception={"agents": ["oracle", {"name": "always", "label": "no"}]})
    code, out = run_here(config)
    assert code == 0, out
    rows = RunStore(tmp_path / "run").read_table("perception").to_pylist()
    mine = {row["item_id"]: row for row in rows if row["agent"] == "no"}
    assert len(mine) == len(ITEMS) and all(row["reply"] == "NO" for row in mine.values())
    expected = {item_id: answer == "NO" for item_id, *_, answer in ITEMS}
    assert {item_id: row["normalized_correct"] for item_id, row in mine.items()} == expected
    assert all(row["normalized_correct"] for row in rows if row["agent"] == "oracle")
    code, out = run_here(config)
    assert code == 0, out
    assert f"{2 * len(ITEMS)} already decided, 0 to run" in " ".join(out.split())


@pytest.mark.ray
@pytest.mark.browser
@pytest.mark.slow
def test_a_drag_plugin_runs_in_a_sweep_where_it_drags_as_it_says(tmp_path: Path, plugin_ray: int) -> None:
    from scratchworld_dist.kinds.drag.items import load_drag_suite

    task = next(t.id for t in load_drag_suite(REPO / "drag-tasks").tasks if t.type == "T1")
    agents = [{"name": "nudge", "params": {"dx": 25}}]
    config = drag_config(tmp_path, tasks={"ids": [task]}, drag={"agents": agents, "settings": ["baseline", "gt_start"]})
    code, out = run_here(config)
    assert code == 0, out
    store = RunStore(tmp_path / "run")
    jobs = {row["job_id"]: row for row in store.read_table("jobs").to_pylist()}
    drags = {row["setting"]: row for row in store.read_table("drags").to_pylist()}
    assert set(drags) == {"baseline", "gt_start"} and all(job["outcome"] != "error" for job in jobs.values())
    assert drags["baseline"]["parse"] == "no_answer" and drags["baseline"]["start_x"] is None
    given = drags["gt_start"]
    assert (given["start_x"], given["start_y"]) == (given["gt_start_x"], given["gt_start_y"])
    assert (given["end_x"], given["end_y"]) == (given["gt_start_x"] + 25, given["gt_start_y"])
