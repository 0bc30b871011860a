"""Prints how close ``scratchworld plan``'s cost estimate comes to what a run then spends (tokens and dollars).

    .venv/bin/python benchmarks/plan_estimate.py [--first quiz_score,sum_two_numbers]
                                                 [--second star_shower,bouncing_ball_stuck]

Two small real sweeps (Ray, Chromium, LiteLLM) of the llm agent, composite and primitive, against the tests' local
OpenAI-compatible server (``tests/support/openai_server.py``) under a priced model name, ``openai/gpt-4o-mini`` with
``api_base`` set, so LiteLLM prices every call as it would OpenAI's. The server answers like a model that follows
each task's golden trajectory in composite mode and fumbles in primitive mode (a click, an unparsable reply, done),
and reports as usage what LiteLLM's token counter counts in each request it gets (the prompts our agent really
sends, screenshots included) and in its reply.

1. The first sweep is planned in a fresh folder: its estimate uses the modes' documented default tokens per step
   and half the step budget per attempt. It then runs.
2. The second sweep, on other tasks, is planned with ``--tokens-from`` the first run (measured tokens per step,
   steps per attempt), then runs.

For each: the estimate, the actual tokens and cost from the run's rows, the error, and the upper bound.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

import yaml

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from scratchworld_dist._plan_preview import PlanPreview, preview_plan  # noqa: E402
from scratchworld_dist.results import RunStore  # noqa: E402
from scratchworld_dist.suites import load_suite  # noqa: E402
from scratchworld_dist.sweep import load_sweep_config  # noqa: E402
from tests.support.openai_server import Behaviour, OpenAIServer, reply  # noqa: E402

MODEL = "openai/gpt-4o-mini"
KEY_ENV = "PLAN_ESTIMATE_API_KEY"
STEPS = {"composite": 30, "primitive": 10}


def counted(messages: list[dict[str, Any]]) -> int:
    os.environ.setdefault("LITELLM_LOCAL_MODEL_COST_MAP", "True")
    import litellm

    return int(litellm.token_counter(model="gpt-4o-mini", messages=messages))


class GoldenModel:
    """Answers from the conversation: the task by its instruction, the turn by the replies so far."""

    def __init__(self) -> None:
        suite = load_suite(REPO / "tasks")
        self.trajectories = {task.instruction: task.trajectory() or [] for task in suite.tasks}

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        messages = body["messages"]
        system = messages[0]["content"] if isinstance(messages[0]["content"], str) else ""
        turn = sum(1 for m in messages if m["role"] == "assistant")
        if "drag_and_drop" in system:  # primitive mode
            action: dict[str, Any] | None = {"api": "done", "args": {}}
            if turn == 0:
                parts = messages[-1]["content"]
                text = (
                    next((p["text"] for p in parts if p.get("type") == "text"), "") if isinstance(parts, list) else ""
                )
                index = re.search(r"^(\d+)  category_menu_item  Variables ", text, re.M)
                action = {"api": "click", "args": {"index": int(index.group(1))}} if index else action
            elif turn == 1:
                action = None
            return self._reply(messages, action)
        trajectory = next((t for instruction, t in self.trajectories.items() if instruction in system), [])
        if turn < len(trajectory):
            return self._reply(messages, trajectory[turn].model_dump(mode="json", include={"api", "args"}))
        return self._reply(messages, {"api": "done", "args": {}})

    def _reply(self, messages: list[dict[str, Any]], action: dict[str, Any] | None) -> Behaviour:
        text = (
            "I am not sure what to do next."
            if action is None
            else f"Analysis: next step.\n```json\n{json.dumps(action)}\n```"
        )
        answer = counted([{"role": "assistant", "content": text}])
        return reply(text, prompt_tokens=counted(messages), completion_tokens=answer)


def write_config(folder: Path, name: str, tasks: list[str], url: str) -> Path:
    config = {
        "name": name,
        "suite": str(REPO / "tasks"),
        "agent": "llm",
        "models": [{"model": MODEL, "api_base": url, "api_key_env": KEY_ENV, "temperature": 0, "max_tokens": 1024}],
        "tasks": {"ids": tasks},
        "episodes": {"modes": ["composite", "primitive"], "max_steps": STEPS},
        "limits": {"episode_timeout_s": 900, "retries": 1},
        "output": str(folder / name),
    }
    path = folder / f"{name}.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def actual(run_dir: Path) -> tuple[int, int, float]:
    rows = RunStore(run_dir).job_rows()
    return sum(r.input_tokens for r in rows), sum(r.output_tokens for r in rows), sum(r.cost_usd for r in rows)


def error(estimate: float, real: float) -> str:
    return f"{(estimate - real) / real:+.0%}" if real else "n/a"


def report(label: str, preview: PlanPreview, run_dir: Path) -> None:
    tokens_in, tokens_out, cost = actual(run_dir)
    totals = preview.totals
    sources = sorted({line.cost.rates.source for line in preview.lines if line.cost.rates})
    print(f"\n{label}: {preview.totals.to_run} job(s); tokens per step: {'; '.join(sources)}")
    for what, estimate, real in (
        ("input", totals.input_tokens, tokens_in),
        ("output", totals.output_tokens, tokens_out),
    ):
        print(f"  {what + ' tokens':<14} estimated {estimate:>9,}  actual {real:>9,}  error {error(estimate, real)}")
    estimated = totals.cost_usd or 0.0
    print(f"  cost           estimated ${estimated:.5f}  actual ${cost:.5f}  error {error(estimated, cost)}")
    bound = totals.max_cost_usd
    print(f"  upper bound    ${bound:.4f} ({'holds' if bound is not None and cost <= bound else 'BROKEN'})")
    for line in preview.lines:
        rows = [r for r in RunStore(run_dir).job_rows() if r.mode == line.mode]
        steps = sum(r.steps for r in rows)
        per_step = sum(r.input_tokens for r in rows) / steps if steps else 0.0
        print(
            f"  {line.mode:<9} actual {steps} steps over {len(rows)} attempt(s), {per_step:,.0f} input tokens/step; "
            f"estimated {line.cost.input_tokens:,} input tokens"
        )


def run(config: Path) -> None:
    done = subprocess.run(
        [str(Path(sys.executable).with_name("scratchworld")), "run", str(config), "--progress", "none"],
        capture_output=True,
        text=True,
        env={**os.environ, KEY_ENV: "sk-local-benchmark"},
        cwd=REPO,
    )
    if done.returncode not in (0, 1):
        raise SystemExit(f"the sweep failed:\n{done.stdout}\n{done.stderr}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--first", default="quiz_score,sum_two_numbers")
    parser.add_argument("--second", default="star_shower,bouncing_ball_stuck")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as temp, OpenAIServer(responder=GoldenModel()) as server:
        folder = Path(temp)
        first = write_config(folder, "first", args.first.split(","), server.url)
        preview = preview_plan(load_sweep_config(first))
        run(first)
        report(f"1. {args.first}, planned fresh (defaults)", preview, folder / "first")
        second = write_config(folder, "second", args.second.split(","), server.url)
        preview = preview_plan(load_sweep_config(second), [folder / "first"])
        run(second)
        report(f"2. {args.second}, planned with --tokens-from the first run", preview, folder / "second")
        print(f"\nmodel calls answered: {server.count}")


if __name__ == "__main__":
    main()
