"""Running an episode or a regrade on a worker: the actor's former episode and regrade branches, unchanged."""

from __future__ import annotations

from pydantic import BaseModel

from workers.agent_api import agent_code, build_agent
from workers.contract import AgentUnavailableError, EpisodeSpec, JobResult, RegradeSpec, TaskPayload, WorkerJob
from workers.episode import regrade, run_synthetic
from workers.kinds._protocol import WorkerHost


async def run_task(host: WorkerHost, spec: WorkerJob, task: BaseModel) -> JobResult:
    if isinstance(spec, RegradeSpec):
        if not isinstance(task, TaskPayload):
            return JobResult.errored(spec, "internal_error", "a regrade needs an episode task's payload")
        runner = await host.browser()
        return await host.in_browser(spec, runner.session, regrade(runner.evaluator, spec, task))
    if not (isinstance(spec, EpisodeSpec) and isinstance(task, TaskPayload)):
        return JobResult.errored(spec, "internal_error", "an episode needs an episode spec and a task payload")
    if host.synthetic is not None and host.synthetic.covers(task.task_id):
        return await run_synthetic(spec, task, host.synthetic)
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
    runner = await host.browser()
    return await host.in_browser(spec, runner.session, runner.run(spec, task, agent))
