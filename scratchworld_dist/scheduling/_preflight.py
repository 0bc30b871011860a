"""Preflight: every model a sweep calls is checked (its key and base URL set, and by default one smallest call
made) where the workers run, before any job starts, so a wrong key stops the run in seconds, naming the model
(one line per broken one); or, when asked, the run goes on without their jobs.

Workers read keys and base URLs from their own environment: with a private local Ray that is the driver's,
so the checks run here; on a cluster they run in a task on a node with browser slots (no editor, no slot).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from rich.console import Console

from scratchworld_dist.kinds import job_kind
from scratchworld_dist.sweep import JobSpec, KindConfig, RunPlan
from workers.contract import ModelCheck, ModelSpec, NodeReport, Preflight, RetryPolicy, ScratchWorldError
from workers.llm import check_models


class ModelCalls:
    """The models each job of one sweep calls (a job of a scripted agent may carry a model label it never calls)."""

    def __init__(self, plan: RunPlan) -> None:
        config = plan.config
        kind = job_kind(config.benchmark, KindConfig)
        self.synthetic = plan.synthetic
        self.callable = [m.spec() for m in config.models] if kind.needs_model(config) else []
        self.callable += kind.helper_models(config.agent)

    def of(self, job: JobSpec) -> list[ModelSpec]:
        synthetic = self.synthetic
        if synthetic is not None and synthetic.covers(job.task_id):
            return []
        return [spec for spec in (job.model, *job.extra_models) if spec is not None and spec in self.callable]

    def over(self, jobs: Iterable[JobSpec]) -> list[ModelSpec]:
        """Every model ``jobs`` call, once each, in the order they first appear."""
        found: list[ModelSpec] = []
        for job in jobs:
            found += [spec for spec in self.of(job) if spec not in found]
        return found


NODE_GRACE_S = 120.0
"""Time a node may take beyond the probes' own bound (starting a Python worker, importing LiteLLM)."""


class PreflightError(ScratchWorldError):
    """A model the sweep calls cannot be called; the message names each, one line apiece."""


def run_preflight(plan: RunPlan, jobs: Sequence[JobSpec], node: NodeReport | None) -> Preflight | None:
    """The models ``jobs`` of ``plan`` call, checked (and probed, per its config's ``probe``) on the driver, or
    on ``node`` of a cluster; None when they call no model."""
    config = plan.config
    models = ModelCalls(plan).over(jobs)
    if not models:
        return None
    probe = config.probe if config.probe is not None else any(spec.api_key_env for spec in models)
    if node is None:
        return Preflight(probe=probe, where="driver", models=check_models(models, config.llm.retry, probe))
    checks = _on_node(node, models, config.llm.retry, probe)
    return Preflight(probe=probe, where=node.name, models=checks)


def broken_by_settings(plan: RunPlan, jobs: Sequence[JobSpec]) -> bool:
    """Whether a model ``jobs`` call is broken by its settings alone (a key or base URL unset or malformed), which
    the preflight finds without calling anything."""
    models = ModelCalls(plan).over(jobs)
    return any(check.broken for check in check_models(models, plan.config.llm.retry, probe=False))


def _on_node(node: NodeReport, models: list[ModelSpec], policy: RetryPolicy, probe: bool) -> list[ModelCheck]:
    import ray
    from ray.exceptions import GetTimeoutError, RayError
    from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

    remote = ray.remote(check_models).options(
        num_cpus=0, scheduling_strategy=NodeAffinitySchedulingStrategy(node.node_id, soft=False)
    )
    timeout = 2 * policy.max_total_s + NODE_GRACE_S if probe else NODE_GRACE_S
    try:
        return list(ray.get(remote.remote(models, policy, probe), timeout=timeout))
    except (RayError, GetTimeoutError) as exc:
        reason = (str(exc).strip().splitlines() or [type(exc).__name__])[-1][:300]
        raise PreflightError(f"preflight: the models could not be checked on {node.name}: {reason}") from None


def broken_line(check: ModelCheck) -> str:
    """One broken model on one line: its label, LiteLLM string, class and cause."""
    return f"{check.name} ({check.model}): {check.error_class}: {check.cause}"


def refuse_broken(preflight: Preflight | None, skip_broken: bool) -> None:
    """Raise ``PreflightError`` naming each broken model, one line apiece, unless ``skip_broken`` (or none is)."""
    broken = preflight.broken if preflight is not None else []
    if preflight is None or not broken or skip_broken:
        return
    raise PreflightError(
        f"preflight{_where(preflight)}: {len(broken)} of {len(preflight.models)} model(s) cannot be called; no job "
        f"was started (--skip-broken-models runs the other models' jobs):\n{_lines(broken)}"
    )


def settle(
    preflight: Preflight | None, plan: RunPlan, todo: list[tuple[JobSpec, int]], console: Console
) -> list[tuple[JobSpec, int]]:
    """``todo`` without the jobs of broken models (``refuse_broken`` let them through), saying what the preflight
    found; records how many jobs it left out in ``preflight``."""
    if preflight is None:
        return todo
    broken = preflight.broken
    if not broken:
        console.print(_passed(preflight), markup=False, soft_wrap=True)
        return todo
    unusable = {(check.name, check.model) for check in broken}
    calls = ModelCalls(plan)
    kept = [(job, attempt) for job, attempt in todo if not unusable & {(s.name, s.model) for s in calls.of(job)}]
    preflight.left_out_jobs = len(todo) - len(kept)
    console.print(
        f"preflight{_where(preflight)}: {len(broken)} of {len(preflight.models)} model(s) cannot be called; their "
        f"{preflight.left_out_jobs} job(s) are left out of this run (a run without --skip-broken-models plans "
        f"them again):\n{_lines(broken)}",
        markup=False,  # causes quote providers
        soft_wrap=True,  # one line per model, whatever the console's width
    )
    return kept


def _where(preflight: Preflight) -> str:
    return "" if preflight.where == "driver" else f" on {preflight.where}"


def _lines(broken: list[ModelCheck]) -> str:
    return "\n".join(f"  {broken_line(check)}" for check in broken)


def _passed(preflight: Preflight) -> str:
    count, where = len(preflight.models), _where(preflight)
    if not preflight.probe:
        return f"preflight{where}: the keys and base URLs of {count} model(s) are set (not probed)"
    tokens = sum(check.input_tokens + check.output_tokens for check in preflight.models)
    return f"preflight{where}: {count} model(s) answered a probe ({tokens} token(s), ${preflight.cost_usd:.6f})"
