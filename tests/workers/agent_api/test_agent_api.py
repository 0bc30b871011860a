"""The agent protocol as an episode drives it: start, act with the last result, finish; and what an agent may not do."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from tests.conftest import SUITE_DIR
from tests.support.openai_server import OpenAIServer, reply
from workers.agent_api import AgentBase, EpisodeEnd, StepResult, TaskContext
from workers.contract import Action, CompositeAction, Done, LoadProject, ModelSpec, Observation
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec

pytestmark = pytest.mark.browser


@pytest.fixture(scope="module")
def content() -> TaskContent:
    return read_task(load_suite(SUITE_DIR).task("sum_two_numbers"))


def spec(content: TaskContent) -> EpisodeSpec:
    (job,) = plan_jobs(
        EpisodeMatrix(models=[None], modes=["composite"], agent="noop", tasks=[content], seeds=[0], max_steps=10)
    )
    return worker_job(job, 1, 120)


class Recorder(AgentBase):
    """Tries a privileged action, then an editing call, then stops; notes every call it gets."""

    def __init__(self, plan: list[Any], fail_in: str | None = None) -> None:
        super().__init__()
        self.plan, self.fail_in = plan, fail_in
        self.calls: list[tuple[str, Any]] = []

    async def start(self, context: TaskContext) -> None:
        self.calls.append(("start", (context.task_id, context.mode, context.max_steps)))
        if self.fail_in == "start":
            raise KeyError("no such thing")
        if self.fail_in == "privileges":
            context.privileges  # noqa: B018 - reading it is the point

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        self.calls.append(("act", (type(observation).__name__, last)))
        return self.plan.pop(0)

    async def finish(self, end: EpisodeEnd) -> None:
        self.calls.append(("finish", end))


async def test_an_episode_calls_start_then_act_with_each_result_then_finish(
    episode_runner: EpisodeRunner, content: TaskContent
) -> None:
    agent = Recorder([LoadProject(sb3=b"PK"), CompositeAction(api="select_stage"), Done()])
    result = await episode_runner.run(spec(content), content.payload, agent)
    assert result.stop_reason == "done" and result.outcome == "failed"  # judged, and nothing was built
    names = [name for name, _ in agent.calls]
    assert names == ["start", "act", "act", "act", "finish"]
    assert agent.calls[0][1] == ("sum_two_numbers", "composite", 10)
    (first_seen, no_result), (_, refused), (_, selected) = (args for name, args in agent.calls if name == "act")
    assert first_seen == "CompositeObservation" and no_result is None
    # Only oracles may replace the project: a plugin's LoadProject costs the step, it is not carried out.
    assert refused == StepResult(
        ok=False,
        error_code="PRIVILEGED_ACTION",
        error_message="only privileged agents (oracles) may replace the whole project",
    )
    assert selected.ok  # type: ignore[union-attr]
    assert agent.calls[-1][1] == EpisodeEnd(stop_reason="done", steps=3)


@pytest.mark.parametrize(
    ("fail_in", "plan", "fragment"),
    [
        ("start", [], "failed to start: KeyError: 'no such thing'"),
        ("privileges", [], "only privileged agents (oracles) may read the solution or the editor"),
        (None, ["not an action"], "returned a str at step 0, not an action"),
    ],
)
async def test_an_agent_that_breaks_ends_the_job_as_agent_error_with_its_traceback(
    episode_runner: EpisodeRunner, content: TaskContent, fail_in: str | None, plan: list[Any], fragment: str
) -> None:
    agent = Recorder(plan, fail_in)
    result = await episode_runner.run(spec(content), content.payload, agent)
    assert (result.outcome, result.error_class) == ("error", "agent_error")
    assert fragment in (result.error_message or "")
    last = result.steps[-1]
    assert (last.action, last.error_code) == ("agent_error", "agent_error")
    assert "Traceback" in (last.error_message or "") or fail_in is None
    assert agent.calls[-1] == ("finish", EpisodeEnd(stop_reason="agent_error", steps=len(result.steps) - 1))


class Judge(AgentBase):
    """Asks its model in start (a plan) and in finish (a self-evaluation, as AWM does); acts without it."""

    needs_model = True

    def __init__(self, crash_after_plan: bool = False) -> None:
        super().__init__()
        self.crash_after_plan = crash_after_plan

    async def start(self, context: TaskContext) -> None:
        self.model = context.model()
        await self.model.complete([{"role": "user", "content": "plan"}])
        if self.crash_after_plan:
            raise RuntimeError("the plan makes no sense")

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        return Done()

    async def finish(self, end: EpisodeEnd) -> None:
        await self.model.complete([{"role": "user", "content": f"did it work? ({end.stop_reason})"}])


@pytest.fixture
def model_server(monkeypatch: pytest.MonkeyPatch) -> Iterator[OpenAIServer]:
    monkeypatch.setenv("SCRATCHWORLD_TEST_JUDGE_KEY", "sk-judge")
    with OpenAIServer(default=reply("fine", prompt_tokens=50, completion_tokens=5)) as server:
        yield server


@pytest.mark.usefixtures("litellm_clients")
@pytest.mark.parametrize("crash", [False, True])
async def test_calls_in_start_and_finish_are_booked_too(
    episode_runner: EpisodeRunner, content: TaskContent, model_server: OpenAIServer, crash: bool
) -> None:
    model = ModelSpec(
        name="m", model="openai/gpt-4o-mini", api_base=model_server.url, api_key_env="SCRATCHWORLD_TEST_JUDGE_KEY"
    )
    (job,) = plan_jobs(
        EpisodeMatrix(models=[model], modes=["composite"], agent="llm", tasks=[content], seeds=[0], max_steps=10)
    )
    result = await episode_runner.run(worker_job(job, 1, 120), content.payload, Judge(crash))
    assert model_server.count == 2  # the plan, and the self-evaluation however the episode ended
    assert result.llm_calls == 2 and result.input_tokens == 100 and result.cost_usd > 0
    if crash:
        start, crashed = result.steps
        assert (start.action, start.llm_calls, crashed.action) == ("start", 2, "agent_error")
    else:
        (done,) = result.steps
        assert (done.action, done.llm_calls, done.reply) == ("done", 2, "fine")
        texts = [m["content"] for m in done.prompt]  # type: ignore[index]
        assert texts == ["plan", "fine", "did it work? (done)"]
