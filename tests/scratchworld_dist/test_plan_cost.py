"""``scratchworld plan``'s cost before spending: LiteLLM's prices times tokens per step (measured in earlier runs of
the suite, else the mode's documented default), an upper bound from step budgets, the context limit and retries,
lines and total that agree, a run directory ``run`` would refuse, and the same plan as JSON."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist._plan_preview import PlanPreview, preview_plan
from scratchworld_dist._run_status import RunStatus
from scratchworld_dist._sweep_manifest import checked_manifest
from scratchworld_dist.kinds.tasks._token_rates import EPISODE_RATES
from scratchworld_dist.results import JobRecord, RunStore, write_manifest
from scratchworld_dist.sweep import SweepConfig, SweepOverrides, load_sweep_config, plan_run
from tests.conftest import SUITE_DIR
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job

PRICED = {"model": "openai/gpt-4o-mini", "api_base": "http://127.0.0.1:9/v1", "max_tokens": 500}
UNPRICED = {"model": "openai/scripted", "name": "scripted", "api_base": "http://127.0.0.1:9/v1"}


def write(tmp_path: Path, name: str = "sweep", **fields: Any) -> Path:
    path = tmp_path / f"{name}.yaml"
    config = {"name": name, "suite": str(SUITE_DIR), "agent": "llm", "models": [PRICED], "tasks": {"limit": 3}}
    config["episodes"] = {"max_steps": 20, "modes": ["composite"]}
    path.write_text(yaml.safe_dump({**config, "output": str(tmp_path / name), **fields}))
    return path


def litellm_info(model: str) -> dict[str, Any]:
    os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
    import litellm

    return dict(litellm.get_model_info(model))


def recorded(config: SweepConfig, rows: list[dict[str, Any]]) -> Path:
    """``config``'s run directory with its manifest and one committed attempt per row (of its first jobs)."""
    plan = plan_run(config)
    run_dir = config.run_dir()
    run_dir.mkdir(parents=True)
    write_manifest(run_dir, checked_manifest(plan, run_dir, force=False))
    store = RunStore(run_dir)
    store.open_for_writing()
    for spec, fields in zip(plan.jobs, rows, strict=False):
        current = {"suite_hash": plan.suite.hash, "harness_fingerprint": plan.harness.digest}
        store.commit(JobRecord(job=job(spec.job_id, mode=spec.mode, **current, **fields)))
    store.close()
    return run_dir


def test_a_fresh_model_is_priced_from_litellm_with_the_modes_default_tokens_and_bounded(tmp_path: Path) -> None:
    preview = preview_plan(load_sweep_config(write(tmp_path)))
    (line,) = preview.lines
    info, rates = litellm_info("openai/gpt-4o-mini"), EPISODE_RATES["composite"]
    steps = 3 * 20 * rates.budget_share  # three jobs, half their step budget each
    assert line.cost.rates == rates
    assert (line.cost.input_tokens, line.cost.output_tokens) == (steps * rates.input_per_step, steps * 250)
    expected = steps * (rates.input_per_step * info["input_cost_per_token"] + 250 * info["output_cost_per_token"])
    assert line.cost.cost_usd == pytest.approx(expected)
    calls = 3 * 20 * (1 + 2)  # every step of every attempt: two retries by default
    assert line.model_calls == calls
    bound = calls * (info["max_input_tokens"] * info["input_cost_per_token"] + 500 * info["output_cost_per_token"])
    assert line.cost.max_cost_usd == pytest.approx(bound)  # max_tokens 500 caps each reply
    assert preview.totals.cost_usd == line.cost.cost_usd and preview.totals.max_cost_usd == line.cost.max_cost_usd
    (model,) = preview.models
    assert model.price is not None and model.price.input_usd_per_token == info["input_cost_per_token"]


def test_rows_and_total_agree_when_a_model_has_no_price(tmp_path: Path) -> None:
    done = invoke("plan", str(write(tmp_path, models=[PRICED, UNPRICED])))
    assert done.returncode == 0, done.stderr
    rows = {
        line.split()[0]: line.split()
        for line in done.stdout.splitlines()
        if line.startswith("openai/gpt") or line.startswith("scripted ")
    }
    priced_cost, scripted_cost = rows["openai/gpt-4o-mini"][8], rows["scripted"][8]
    assert re.fullmatch(r"\$\d+\.\d{4}", priced_cost) and scripted_cost == "unknown"
    assert f"estimated cost unknown ({priced_cost} for the lines with a price)" in done.stdout
    assert (
        "LiteLLM has no price for openai/scripted (give params input_cost_per_token, output_cost_per_token)"
        in done.stdout
    )
    priced = invoke(
        "plan",
        str(write(tmp_path, models=[PRICED, UNPRICED])),
        "-M",
        "scripted:input_cost_per_token=1e-6",
        "-M",
        "scripted:output_cost_per_token=2e-6",
    )
    assert "estimated cost $" in priced.stdout and "unknown (" not in priced.stdout  # the params price it


def test_tokens_are_measured_in_runs_of_the_same_suite_and_mode(tmp_path: Path) -> None:
    earlier = load_sweep_config(write(tmp_path, "earlier", seeds=[5]))
    measured_dir = recorded(
        earlier,
        [
            {
                "model": "gpt-4o-mini",
                "litellm_model": "openai/gpt-4o-mini",
                "steps": 8,
                "input_tokens": 8 * 3000,
                "output_tokens": 8 * 90,
                "llm_calls": 8,
            }
        ]
        * 2,
    )
    other_suite = tmp_path / "other"
    recorded(load_sweep_config(write(tmp_path, "other")), [{"steps": 1, "input_tokens": 1}])
    manifest = json.loads((other_suite / "manifest.json").read_text())
    manifest["suite"]["name"] = "another-suite"
    (other_suite / "manifest.json").write_text(json.dumps(manifest))
    preview = preview_plan(load_sweep_config(write(tmp_path)), [measured_dir, other_suite])
    (line,) = preview.lines
    assert line.cost.rates is not None and line.cost.rates.source.startswith(
        "measured: 2 composite attempt(s), openai/gpt-4o-mini's"
    )
    assert (line.cost.input_tokens, line.cost.output_tokens) == (3 * 8 * 3000, 3 * 8 * 90)
    assert (
        f"--tokens-from {other_suite}: a run of suite another-suite, not scratchworld-dist-core; not used"
        in preview.notices
    )
    done = invoke("plan", str(write(tmp_path)), "--tokens-from", str(tmp_path / "nothing"))
    assert done.returncode == 2 and f"--tokens-from {tmp_path / 'nothing'}: not a run directory" in done.stderr


def test_plan_says_run_would_refuse_a_folder_holding_another_sweep(tmp_path: Path) -> None:
    other = load_sweep_config(write(tmp_path, "first", seeds=[3]))
    recorded(other, [])
    done = invoke("plan", str(write(tmp_path)), "--out", str(other.run_dir()))
    assert done.returncode == 0, done.stderr
    assert (
        f"warning: run would refuse this directory: {other.run_dir()} holds results of another sweep (sweep config "
        in done.stdout
    )
    same = invoke("plan", str(write(tmp_path, "first", seeds=[3])))
    assert "would refuse" not in same.stdout


def test_plan_and_status_as_json(tmp_path: Path) -> None:
    config_file = write(tmp_path, tags={"team": "evals"})
    config = load_sweep_config(config_file, changes=SweepOverrides(tags=["ticket=52"]))
    run_dir = recorded(config, [{"outcome": "passed"}, {"outcome": "error"}])
    done = invoke("plan", str(config_file), "--json", "--tag", "ticket=52")
    assert done.returncode == 0, done.stderr
    preview = PlanPreview.model_validate_json(done.stdout)
    assert preview == preview_plan(config)
    assert (preview.totals.to_run, preview.totals.decided, preview.tags) == (2, 1, {"team": "evals", "ticket": "52"})
    status = invoke("status", str(run_dir), "--json")
    assert status.returncode == 0, status.stderr
    parsed = RunStatus.model_validate_json(status.stdout)
    assert (parsed.planned_jobs, parsed.passed, parsed.error, parsed.not_yet_run) == (3, 1, 1, 1)
    assert parsed.errors == {"EditorCrashedError": 1} and parsed.tags == {"team": "evals", "ticket": "52"}
    text = invoke("status", str(run_dir))
    assert "tags: team=evals ticket=52" in text.stdout
    report = invoke("report", str(run_dir), "--format", "json")
    assert json.loads(report.stdout)["runs"][0]["tags"] == {"team": "evals", "ticket": "52"}  # carried to reports
    assert "Tags (sweep): team=evals, ticket=52" in invoke("report", str(run_dir)).stdout
    exported = invoke("export", str(run_dir), "--format", "leaderboard", "--out", str(tmp_path / "board"))
    assert exported.returncode == 0, exported.stderr
    board = json.loads((tmp_path / "board" / "leaderboard.json").read_text())
    assert board["runs"][0]["tags"] == {"team": "evals", "ticket": "52"}  # and to the leaderboard export
