"""Compares the two episode clocks on the same jobs: do agents' verdicts change with how time passes on their page?

    .venv/bin/python benchmarks/episode_clock.py [--suite PATH] [--task-list FILE] [--tasks a,b] [--plans DIR]
        [--agents oracle,llm] [--modes composite,primitive] [--llm-tasks N] [--delay 2] [--keep DIR]

For each agent, one real sweep per episode clock (``virtual``, then ``real``) over the same tasks, seed and
modes, on a private local Ray; the evaluation clock is the suite's default for both, so only the episode
clock differs. ``oracle`` replays (composite) or acts out (primitive) each task's trajectory (a suite of
ours brings its own; an upstream clone needs ``--plans``, the folder ``scratchworld oracle-plan`` wrote).
``llm`` is the LLM agent in composite mode against ``tests/support/openai_server.py``, which answers each
request ``--delay`` seconds after it arrived with the next action of the task's trajectory (the task is
found by its instruction in the prompt), then ``done``: on the real clock the project runs on while the
model "thinks", on the virtual one it does not. ``--llm-tasks`` takes the first N selected tasks.

Prints per agent and mode: jobs, verdicts per clock, jobs whose outcome differs, and test verdicts that
differ, split by the suite's known test stability (stable, unstable, unchecked); then every differing
job and test, and each sweep's wall time and mean episode time.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path
from typing import Any

from rich.console import Console

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # for tests.support.openai_server, the tests' model server

from scratchworld_dist import load_suite
from scratchworld_dist._run import run_sweep
from scratchworld_dist.results import RunStore
from scratchworld_dist.suites import Task, read_trajectory
from scratchworld_dist.sweep import SweepConfig
from tests.support.openai_server import Behaviour, OpenAIServer

REPO = Path(__file__).resolve().parents[1]
CLOCKS = ("virtual", "real")
KEY_ENV = "SCRATCHWORLD_EPISODE_CLOCK_API_KEY"
Verdicts = dict[tuple[str, str], tuple[str, dict[str, tuple[bool, bool | None]]]]
"""(task, mode) → (outcome, test name → (passed, unstable))."""


class TrajectoryModel:
    """The server's responder: each task's trajectory, one action per request, ``delay`` seconds after it came."""

    def __init__(self, tasks: list[Task], plans: Path | None, delay: float) -> None:
        self.delay = delay
        self.actions: dict[str, list[dict[str, Any]]] = {}
        self.instructions: dict[str, str] = {}
        for task in tasks:
            path = task.golden_trajectory or (plans / f"{task.id}.json" if plans else None)
            if path is None or not path.is_file():
                continue
            self.actions[task.id] = [action.model_dump(mode="json") for action in read_trajectory(path)]
            self.instructions[task.id] = task.instruction
        self.served: Counter[str] = Counter()
        self._lock = threading.Lock()

    def reset(self) -> None:
        with self._lock:
            self.served.clear()

    def _task_of(self, body: dict[str, Any]) -> str | None:
        text = json.dumps(body.get("messages", []))
        found = [task for task, instruction in self.instructions.items() if json.dumps(instruction)[1:-1] in text]
        return max(found, key=lambda task: len(self.instructions[task])) if found else None

    def __call__(self, body: dict[str, Any]) -> Behaviour:
        task = self._task_of(body)
        with self._lock:
            index = self.served[task or ""]
            self.served[task or ""] += 1
        actions = self.actions.get(task or "", [])
        action = actions[index] if index < len(actions) else {"api": "done", "args": {}}
        text = f"Next step.\n```json\n{json.dumps(action)}\n```"
        return Behaviour("hang", text=text, seconds=self.delay, prompt_tokens=2000, completion_tokens=40)


def sweep_config(args: argparse.Namespace, agent: str, clock: str, ids: list[str], url: str, out: Path) -> SweepConfig:
    modes = args.modes.split(",") if agent == "oracle" else ["composite"]
    raw: dict[str, Any] = {
        "name": f"episode-clock-{agent}-{clock}",
        "suite": args.suite,
        "tasks": {"ids": ids, **({"task_list": args.task_list} if args.task_list else {})},
        "agent": agent,
        "seeds": 1,
        "episodes": {"modes": modes, "max_steps": {"composite": 200, "primitive": 1500}, "episode_clock": clock},
        "limits": {"episode_timeout_s": 1200, "retries": 0, "pages_per_worker": args.pages, "browser_slots": 2},
        "output": out,
    }
    if args.plans:
        raw["episodes"]["oracle_trajectories"] = args.plans
    if agent == "llm":
        model = {"model": "openai/gpt-4o-mini", "name": "scripted", "temperature": 0, "api_base": url}
        raw["models"] = [{**model, "api_key_env": KEY_ENV}]
    return SweepConfig.model_validate(raw)


def verdicts_of(run_dir: Path) -> tuple[Verdicts, float]:
    store = RunStore(run_dir)
    jobs = store.read_table("jobs").to_pylist()
    tests = store.read_table("tests").to_pylist()
    found: Verdicts = {}
    for job in jobs:
        names = {
            row["name"]: (row["passed"], row.get("unstable"))
            for row in tests
            if row["job_id"] == job["job_id"] and row["attempt"] == job["attempt"]
        }
        found[(job["task_id"], job["mode"])] = (job["outcome"], names)
    mean_episode = sum(job["episode_s"] for job in jobs) / len(jobs) if jobs else 0.0
    return found, mean_episode


def compare(agent: str, runs: dict[str, Verdicts]) -> list[str]:
    virtual, real = runs["virtual"], runs["real"]
    lines = []
    for mode in sorted({mode for _, mode in virtual}):
        keys = sorted(key for key in virtual.keys() & real.keys() if key[1] == mode)
        passed = {clock: sum(runs[clock][key][0] == "passed" for key in keys) for clock in CLOCKS}
        outcome_diffs = [key for key in keys if virtual[key][0] != real[key][0]]
        test_diffs: dict[str, list[str]] = {"stable": [], "unstable": [], "unchecked": []}
        compared: Counter[str] = Counter()
        for key in keys:
            a, b = virtual[key][1], real[key][1]
            for name in a.keys() | b.keys():
                marks = {a.get(name, (None, None))[1], b.get(name, (None, None))[1]}
                kind = "unstable" if True in marks else "stable" if False in marks else "unchecked"
                compared[kind] += 1
                if a.get(name, (None,))[0] != b.get(name, (None,))[0]:
                    test_diffs[kind].append(f"{key[0]} {name!r}")
        lines.append(
            f"{agent:7} {mode:10} jobs {len(keys):3}  passed virtual {passed['virtual']:3} real {passed['real']:3}  "
            f"outcomes differ {len(outcome_diffs)}  tests differ: "
            + ", ".join(f"{kind} {len(test_diffs[kind])}/{compared[kind]}" for kind in test_diffs)
        )
        for key in outcome_diffs:
            lines.append(f"    outcome {key[0]}: virtual {virtual[key][0]}, real {real[key][0]}")
        for kind, found in test_diffs.items():
            for item in found:
                lines.append(f"    {kind} test {item}")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--suite", type=Path, default=REPO / "tasks", help="suite folder (default: ours)")
    parser.add_argument("--task-list", help="an upstream clone's task list")
    parser.add_argument("--tasks", help="comma-separated task ids (default: all selected)")
    parser.add_argument("--plans", type=Path, help="planned trajectories (scratchworld oracle-plan --out)")
    parser.add_argument("--agents", default="oracle,llm", help="oracle and/or llm")
    parser.add_argument("--modes", default="composite,primitive", help="the oracle's modes")
    parser.add_argument("--llm-tasks", type=int, default=16, help="the llm agent runs the first N tasks")
    parser.add_argument("--delay", type=float, default=2.0, help="seconds the scripted model takes to answer")
    parser.add_argument("--pages", type=int, default=2, help="pages per worker")
    parser.add_argument("--keep", type=Path, help="keep the run directories under this folder")
    args = parser.parse_args()
    suite = load_suite(args.suite, task_list=args.task_list)
    wanted = [t.strip() for t in args.tasks.split(",") if t.strip()] if args.tasks else None
    tasks = suite.select(ids=wanted)
    os.environ[KEY_ENV] = "sk-episode-clock-benchmark"  # the workers of the private Ray inherit it
    model = TrajectoryModel(tasks, args.plans, args.delay)
    report: list[str] = []
    timings: list[str] = []
    with tempfile.TemporaryDirectory(prefix="episode-clock-") as tmp, OpenAIServer(responder=model) as server:
        root = args.keep or Path(tmp)
        for agent in args.agents.split(","):
            ids = [task.id for task in tasks]
            if agent == "llm":
                ids = [task_id for task_id in ids if task_id in model.actions][: args.llm_tasks]
            runs: dict[str, Verdicts] = {}
            for clock in CLOCKS:
                model.reset()
                config = sweep_config(args, agent, clock, ids, server.url, root / f"{agent}-{clock}")
                started = time.perf_counter()
                run_sweep(config, console=Console(quiet=True))
                wall = time.perf_counter() - started
                runs[clock], mean_episode = verdicts_of(config.run_dir())
                timings.append(
                    f"{agent} {clock}: {len(runs[clock])} job(s), sweep {wall:.0f} s, mean episode {mean_episode:.1f} s"
                )
                print(timings[-1], file=sys.stderr, flush=True)
            report.extend(compare(agent, runs))
    print(f"{suite.name}: {len(tasks)} task(s); llm: {args.llm_tasks} task(s), model answering after {args.delay:g} s")
    print("\n".join(report))
    print("\n".join(timings))


if __name__ == "__main__":
    main()
