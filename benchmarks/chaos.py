"""Chaos sweep: a mixed real/synthetic sweep on a local two-node Ray while faults are injected.

    .venv/bin/python benchmarks/chaos.py [--seed 7] [--jobs 156] [--fault-rate 0.3] [--workdir DIR]

The sweep (llm agent, composite mode) runs ``--real-tasks`` as real browser episodes whose model
is a local OpenAI-compatible server (``tests/support/openai_server.py``) replaying each task's golden
trajectory, or answering ``done`` at once for ``--lazy-tasks`` (a failed verdict), and every other
task as a synthetic episode. Two ``ray start`` nodes on this host hold the workers; each driver
is ``scratchworld run`` in its own process group. While it runs, a seeded schedule tied to
progress (committed attempts) SIGKILLs the driver 3 times (and resumes at once), a worker actor
5 times and a Chromium renderer or browser of a worker 5 times, and the server answers
``--fault-rate`` of all model calls with a 429, a 500 or a timeout. After the last fault the
sweep is resumed until every job has a verdict or ``--max-resumes`` runs are spent.

Prints the fault log (time, fault, target), the sessions, and the invariants with PASS/FAIL and
their figures; exits 1 if any invariant fails. Everything it started is stopped at the end.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # for tests.support.openai_server, the tests' model server

import yaml
from _chaos.cluster import LocalCluster
from _chaos.faults import Fault, Injector, plan_faults
from _chaos.invariants import Check, check_run
from _chaos.model import FAULTS, ChaoticModel

from scratchworld_dist._run import RunPlan, plan_run
from scratchworld_dist.results import RunStore, effective_rows
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import load_sweep_config
from tests.support.openai_server import OpenAIServer

REPO = Path(__file__).resolve().parents[1]
SCRATCHWORLD = str(Path(sys.executable).with_name("scratchworld"))
POLL_S = 0.25
REAL_TASKS = "bouncing_ball_stuck,traffic_light_skips_yellow,click_counter_reset"
SYNTHETIC_FAILS = "power_of_number"
REQUEST_TIMEOUT_S = 2.0


class Driver:
    """One ``scratchworld run`` in its own process group, its output in a log file."""

    def __init__(self, config: Path, log: Path, env: dict[str, str], started: float) -> None:
        self.log = log
        self.began_s = time.monotonic() - started
        self.ended_s: float | None = None
        self.killed = False
        with log.open("wb") as out:
            self.process = subprocess.Popen(
                [SCRATCHWORLD, "run", str(config)],
                stdout=out,
                stderr=subprocess.STDOUT,
                env=env,
                start_new_session=True,
            )

    def kill(self, started: float) -> None:
        """SIGKILL the driver itself (as a crash would), then reap its group."""
        with contextlib.suppress(ProcessLookupError):
            os.kill(self.process.pid, signal.SIGKILL)
        self.process.wait()
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.process.pid, signal.SIGKILL)
        self.killed = True
        self.ended_s = time.monotonic() - started

    def summary(self) -> str:
        text = " ".join(self.log.read_text(errors="replace").split())  # rich wraps its lines
        todo = re.search(r"(\d+) already decided, (\d+) to run", text)
        ran = re.search(r"ran \d+ attempt\(s\): [^;]*", text)
        started = f"{todo.group(2)} to run" if todo else "-"
        end = "SIGKILLed" if self.killed else f"exit {self.process.returncode}"
        span = f"{self.began_s:7.1f}-{self.ended_s or 0:7.1f} s"
        return f"{span}  pid {self.process.pid:<7} {started:>10}  {end:<10} {ran.group(0) if ran else ''}"


class Campaign:
    """The sweep, its drivers and the injector, from the first driver to the last resume."""

    def __init__(
        self, args: argparse.Namespace, config: Path, plan: RunPlan, cluster: LocalCluster, env: dict[str, str]
    ) -> None:
        self.args = args
        self.config = config
        self.plan = plan
        self.run_dir = plan.config.run_dir()
        self.cluster = cluster
        self.env = env
        self.started = time.monotonic()
        self.injector = Injector(args.seed, cluster, self.started)
        self.drivers: list[Driver] = []
        self.missed: list[Fault] = []
        self.problems: list[str] = []

    def driver(self) -> Driver:
        log = self.config.with_name(f"driver-{len(self.drivers) + 1}.log")
        driver = Driver(self.config, log, self.env, self.started)
        self.drivers.append(driver)
        print(f"  {driver.began_s:7.1f} s  driver {len(self.drivers)} started (pid {driver.process.pid})", flush=True)
        return driver

    def committed(self) -> int:
        if not (self.run_dir / "manifest.json").exists():
            return 0
        return RunStore(self.run_dir).read_table("jobs", columns=["job_id"]).num_rows

    def with_faults(self, faults: list[Fault]) -> None:
        """Run the sweep while the schedule fires; each fault waits until the current driver has committed."""
        pending = list(faults)
        driver = self.driver()
        baseline = self.committed()
        idle_restarts = 0
        while pending:
            self.cluster.processes()  # remember every process of ours, for the cleanup
            committed = self.committed()
            if driver.process.poll() is not None:
                driver.ended_s = time.monotonic() - self.started
                if idle_restarts == 3:  # the sweep finished before the schedule did
                    self.missed = pending
                    return
                idle_restarts += 1
                driver, baseline = self.driver(), committed
                continue
            fault = pending[0]
            if committed >= fault.after and committed > baseline:
                if fault.kind == "driver":
                    driver.kill(self.started)
                    self.injector.record("driver", f"pid {driver.process.pid} scratchworld run", committed)
                    driver, baseline = self.driver(), committed
                    pending.pop(0)
                elif self.injector.kill(fault.kind, committed):
                    pending.pop(0)
            time.sleep(POLL_S)
        self.finish(driver)

    def finish(self, driver: Driver) -> None:
        """Wait for a driver to end on its own, killing it past ``--driver-timeout`` (a hang is a failure)."""
        deadline = time.monotonic() + self.args.driver_timeout
        while driver.process.poll() is None:
            self.cluster.processes()
            if time.monotonic() > deadline:
                driver.kill(self.started)
                self.problems.append(f"driver {driver.process.pid} ran past {self.args.driver_timeout:g} s")
                return
            time.sleep(POLL_S * 2)
        driver.ended_s = time.monotonic() - self.started

    def undecided(self) -> int:
        rows = RunStore(self.run_dir).job_rows()
        decided = {row.job_id for row in effective_rows(rows) if row.outcome != "error"}
        return len({job.job_id for job in self.plan.jobs} - decided)

    def resume_until_decided(self) -> int:
        """Resume until no job lacks a verdict; returns the resumes made."""
        resumes = 0
        while self.undecided() and resumes < self.args.max_resumes:
            resumes += 1
            self.finish(self.driver())
        return resumes


def sweep_config(args: argparse.Namespace, workdir: Path, address: str, synthetic: list[str], seeds: int) -> Path:
    model = {
        "model": "openai/chaos-model",
        "name": "chaos",
        "api_base_env": "SCRATCHWORLD_LLM_BASE_URL",
        "api_key_env": "SCRATCHWORLD_LLM_API_KEY",
        "temperature": 0,
        "max_tokens": 256,
        "rate_limits": {"requests_per_minute": 6000, "max_concurrency": 4, "lease_s": 60},
    }
    retry = {
        "max_attempts": 3,
        "initial_backoff_s": 0.2,
        "max_backoff_s": 2,
        "request_timeout_s": REQUEST_TIMEOUT_S,
        "max_total_s": 60,
        "breaker_failures": 5,
        "breaker_window_s": 60,
        "breaker_cooldown_s": 5,
    }
    config: dict[str, Any] = {
        "name": "chaos",
        "suite": str(REPO / "tasks"),
        "agent": "llm",
        "models": [model],
        "seeds": seeds,
        "llm": {"history_messages": 200, "retry": retry},
        "limits": {"episode_timeout_s": 240, "retries": 2, "pages_per_worker": args.pages},
        "ray": {"address": address},
        "episodes": {
            "modes": ["composite"],
            "max_steps": 40,
            "synthetic": {
                "duration_s": args.synthetic_s,
                "fail_tasks": [t for t in SYNTHETIC_FAILS.split(",") if t in synthetic],
                "tasks": synthetic,
            },
        },
        "output": str(workdir / "run"),
    }
    path = workdir / "chaos.yaml"
    path.write_text(yaml.safe_dump(config, sort_keys=False))
    return path


def fault_checks(campaign: Campaign, faults: list[Fault], model: ChaoticModel, calls: int, rate: float) -> list[Check]:
    planned = Counter("chromium" if f.kind in ("renderer", "browser") else f.kind for f in faults)
    fired = Counter("chromium" if r.kind in ("renderer", "browser") else r.kind for r in campaign.injector.log)
    kinds = Counter(r.kind for r in campaign.injector.log)
    faults_ok = fired == planned and not campaign.missed
    figures = ", ".join(f"{kind} {fired[kind]}/{planned[kind]}" for kind in ("driver", "worker", "chromium"))
    figures += f" (renderer {kinds['renderer']}, browser {kinds['browser']}); not fired {len(campaign.missed)}"
    ratio = model.faulty / calls if calls else 0.0
    by_kind = ", ".join(f"{kind}: {model.counts[kind]}" for kind in FAULTS)
    undecided = campaign.undecided()
    return [
        Check(name="every scheduled fault fired", ok=faults_ok, figures=figures),
        Check(
            name=f"~{rate:.0%} of model calls faulty (counted at the server)",
            ok=calls >= 100 and abs(ratio - rate) <= 0.03,
            figures=f"{model.faulty}/{calls} = {ratio:.1%} ({by_kind})",
        ),
        Check(
            name="every job ends with a verdict (transient faults only)",
            ok=undecided == 0 and not campaign.problems,
            figures=f"{undecided} job(s) left in error; {'; '.join(campaign.problems) or 'no driver hung'}",
        ),
    ]


def print_outcome(
    campaign: Campaign, checks: list[Check], real_tasks: list[str], wall_s: float, resumes: int, leftovers: list[str]
) -> None:
    print("\nfault log (seconds since start, fault, committed attempts, target)")
    for record in campaign.injector.log:
        print(f"  {record.at_s:7.1f} s  {record.kind:<8}  after {record.committed:>4}  {record.target}")
    for fault in campaign.missed:
        print(f"  not fired: {fault.kind} after {fault.after}")
    print(f"\nsessions ({len(campaign.drivers)} drivers, {resumes} resume(s) after the last fault)")
    for driver in campaign.drivers:
        print(f"  {driver.summary()}")
    rows = RunStore(campaign.run_dir).job_rows()
    effective = list(effective_rows(rows))
    outcomes = Counter(row.outcome for row in effective)
    real = Counter(row.outcome for row in effective if row.task_id in real_tasks)
    errors = Counter(row.error_class for row in rows if row.outcome == "error")
    print(
        f"\nwall {wall_s:.0f} s; {len(effective)} jobs: {dict(outcomes)} (real episodes among them: {dict(real)}); "
        f"{len(rows)} attempts, error attempts by class {dict(errors)}"
    )
    left = [row for row in effective if row.outcome == "error"]
    for row in left:
        print(f"  left in error: {row.task_id} seed {row.seed} #{row.attempt}: {row.error_class}: {row.error_message}")
    print(f"processes of ours killed after the nodes stopped: {len(leftovers)}")
    print("\ninvariants")
    for number, check in enumerate(checks, start=1):
        print(f"  {'PASS' if check.ok else 'FAIL'}  {number}. {check.name}: {check.figures}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--jobs", type=int, default=156, help="at least this many jobs (whole seeds of the suite)")
    parser.add_argument("--fault-rate", type=float, default=0.3, help="share of model calls answered with a fault")
    parser.add_argument("--real-tasks", default=REAL_TASKS, help="tasks run as real browser episodes")
    parser.add_argument("--lazy-tasks", default="click_counter_reset", help="real tasks whose model says done at once")
    parser.add_argument("--synthetic-s", type=float, default=2.0, help="length of a synthetic episode")
    parser.add_argument("--slots", type=int, default=2, help="browser slots per node (two nodes)")
    parser.add_argument("--pages", type=int, default=2, help="pages per worker (episodes per browser)")
    parser.add_argument("--max-resumes", type=int, default=5)
    parser.add_argument("--driver-timeout", type=float, default=1800.0)
    parser.add_argument("--workdir", type=Path, help="where the run directory, logs and Ray's files go")
    args = parser.parse_args()

    started = time.monotonic()
    workdir = (args.workdir or Path(tempfile.mkdtemp(prefix="chaos-"))).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    suite = load_suite(REPO / "tasks")
    real = args.real_tasks.split(",")
    synthetic = [task.id for task in suite.tasks if task.id not in real]
    trajectories: dict[str, list[dict[str, Any]]] = {}
    for task_id in real:
        task = suite.task(task_id)
        trajectories[task.instruction] = [
            a.model_dump(mode="json", include={"api", "args"}) for a in task.trajectory() or []
        ]
    lazy = {suite.task(t).instruction for t in args.lazy_tasks.split(",") if t}
    model = ChaoticModel(args.seed, args.fault_rate, trajectories, lazy, REQUEST_TIMEOUT_S)
    server = OpenAIServer(responder=model).start()
    env = {"RAY_AUTH_MODE": "disabled", "SCRATCHWORLD_LLM_BASE_URL": server.url, "SCRATCHWORLD_LLM_API_KEY": "sk-chaos"}
    cluster = LocalCluster(workdir, [args.slots, args.slots], env)
    leftovers: list[str] = []
    try:
        address = cluster.start()
        seeds = math.ceil(args.jobs / len(suite.tasks))
        config = sweep_config(args, workdir, address, synthetic, seeds)
        plan = plan_run(load_sweep_config(config))
        faults = plan_faults(args.seed, len(plan.jobs), drivers=3, workers=5, chromium=5)
        print(
            f"chaos seed {args.seed}: {len(plan.jobs)} jobs ({len(real)} real tasks x {seeds} seeds, the rest "
            f"synthetic) on 2 nodes at {address} x {args.slots} browser slots, {args.pages} page(s) per worker; "
            f"{args.fault_rate:.0%} faulty model calls; workdir {workdir}"
        )
        print("fault schedule (kind after committed attempts): " + ", ".join(f"{f.kind}@{f.after}" for f in faults))
        campaign = Campaign(args, config, plan, cluster, {**os.environ, **env})
        campaign.with_faults(faults)
        resumes = campaign.resume_until_decided()
    finally:
        leftovers = cluster.stop()
        calls = server.count
        server.close()
    checks = check_run(campaign.run_dir, plan) + fault_checks(campaign, faults, model, calls, args.fault_rate)
    print_outcome(campaign, checks, real, time.monotonic() - started, resumes, leftovers)
    return 0 if all(check.ok for check in checks) else 1


if __name__ == "__main__":
    sys.exit(main())
