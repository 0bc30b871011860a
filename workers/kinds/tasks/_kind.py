"""The ``tasks`` kind as a worker runs it: an episode (an agent in the worker's editors, then the evaluation), or
a regrade of the project an episode left (the evaluation alone, in the same recycled editors)."""

from __future__ import annotations

from pydantic import BaseModel

from workers.agent_api import agent_code, build_agent
from workers.contract import AgentUnavailableError, JobResult, TaskPayload, WorkerJob
from workers.kinds._protocol import AgentGroup, WorkerHost
from workers.kinds.tasks._contract import EpisodeSpec, RegradeSpec

REGRADED = "regraded"
"""Stop reason of a regrade's result (the driver keeps the source's in the row)."""


class TasksKind:
    """Episodes and regrades."""

    name = "tasks"
    specs: tuple[type[BaseModel], ...] = (EpisodeSpec, RegradeSpec)
    payloads: tuple[type[BaseModel], ...] = (TaskPayload,)
    code: tuple[str, ...] = ("kinds/tasks/",)
    """This folder: no other kind nor the core imports it (the browser, editor pool and evaluator it runs in are
    every kind's, in ``workers.actor``, ``workers.editor`` and ``workers.evaluation``)."""

    needs_browser = True
    agents: AgentGroup | None = AgentGroup(
        group="scratchworld.agents", methods=("start", "act", "finish"), base="workers.agent_api.Agent"
    )
    """Episode agents: the group plugins have always used."""

    async def run(self, host: WorkerHost, spec: WorkerJob, payload: BaseModel) -> JobResult:
        from workers.evaluation import judged
        from workers.kinds.tasks._runner import EpisodeRunner  # the browser stack, on the first job
        from workers.kinds.tasks._synthetic import run_synthetic

        if not isinstance(payload, TaskPayload):
            return JobResult.errored(spec, "internal_error", "an episode or a regrade needs a task payload")
        if isinstance(spec, RegradeSpec):
            browser = await host.browser()
            work = judged(
                browser.evaluator,
                spec.project,
                payload,
                spec.project_limits,
                spec.job_id,
                spec.attempt,
                REGRADED,
                random_seed=spec.evaluation_seed,
            )
            return await host.in_browser(spec, browser.session, work)
        if not isinstance(spec, EpisodeSpec):
            return JobResult.errored(spec, "internal_error", "an episode needs an episode spec and a task payload")
        if host.synthetic is not None and host.synthetic.covers(payload.task_id):
            return await run_synthetic(spec, payload, host.synthetic)
        try:
            agent = build_agent(spec.agent)
        except AgentUnavailableError as exc:
            return JobResult.errored(spec, "agent_error", str(exc))
        if getattr(agent, "needs_model", False) and spec.model is None:
            return JobResult.errored(spec, "agent_error", f"agent {spec.agent.name} needs a model; the job has none")
        code = agent_code(type(agent))
        if code != spec.agent_code:
            info = host.info_
            message = (
                f"{info.hostname} (node {info.node_id[:12]}) has agent {spec.agent.name} "
                f"with code {code}, the job was planned for {spec.agent_code}: install the same version here"
            )
            return JobResult.errored(spec, "harness_mismatch", message)
        if spec.model is not None:  # once per worker, before the episode: its first step would wait for the import
            await host.load_litellm()
        browser = await host.browser()
        runner = host.kind_state.get(self.name)
        if not isinstance(runner, EpisodeRunner) or runner.browser is not browser:  # one runner per browser
            runner = host.kind_state[self.name] = EpisodeRunner(browser)
        return await host.in_browser(spec, browser.session, runner.run(spec, payload, agent))


TASKS = TasksKind()
