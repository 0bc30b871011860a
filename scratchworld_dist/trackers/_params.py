"""What a tracker records of a run before its first job: the run's parameters, tags and planned jobs."""

from __future__ import annotations

import json

from scratchworld_dist.results import RunManifest
from scratchworld_dist.sweep import RunPlan
from scratchworld_dist.trackers._tally import PlannedJob
from scratchworld_dist.trackers._tracker import RunInfo, redacted


def run_info(plan: RunPlan, manifest: RunManifest, key: str, run_ids: dict[str, str]) -> RunInfo:
    """The run as its trackers record it: models with their settings (key names, never keys; a base URL's
    credentials left out), modes, suite and hash, harness, agent, seeds and the config's hash."""
    config = plan.config
    params: dict[str, str] = {
        "run_name": config.name,
        "benchmark": config.benchmark,
        "agent": config.agent.display,
        "agent_params": _text(config.agent.params),
        "modes": ",".join(sorted({job.mode for job in plan.jobs})),
        "seeds": ",".join(str(seed) for seed in config.seeds),
        "suite": plan.suite.name,
        "suite_hash": plan.suite.hash,
        "harness": plan.harness.digest if plan.harness is not None else "",
        "config_hash": manifest.config_hash,
        "planned_jobs": str(len(plan.jobs)),
    }
    for model in config.models:
        spec = model.spec()
        params[f"model.{spec.name}"] = redacted(_text(spec.model_dump(mode="json", exclude={"name", "rate_limits"})))
    return RunInfo(name=config.name, key=key, params=params, tags=dict(manifest.tags), run_ids=run_ids)


def planned_jobs(plan: RunPlan) -> dict[str, PlannedJob]:
    """Every job of the plan by id, with what its metrics are grouped by."""
    return {job.job_id: PlannedJob(model=job.model_name, mode=job.mode, category=job.category) for job in plan.jobs}


def _text(value: object) -> str:
    return json.dumps(value, sort_keys=True, separators=(",", ":"))
