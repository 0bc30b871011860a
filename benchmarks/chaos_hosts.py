"""A sweep across hosts that share nothing, and a partition of one of them (root only).

    sudo .venv/bin/python benchmarks/chaos_hosts.py [--agent oracle|llm] [--tasks 12] [--seeds 1] [--slots 1]
        [--cut-after 2] [--mend] [--keep DIR]

Makes ``--workers`` + 1 hosts (``tests/support/netns_hosts.py``: each its own network namespace and address
in 10.201.0.0/24, its own /tmp, /dev/shm, home, processes and hostname; the checkout shared read-only) and
runs docs/cluster.md's recipe on them: the head (no browsers) and the driver on host-0, ``--slots`` editors
on each other host. The sweep (composite mode, our suite copied to host-0's disk; the oracle agent, or with
``--agent llm`` the llm agent against a model server on host-0's address that answers each task's golden
trajectory, ``benchmarks/_chaos/host_model.py``, whose key only the worker hosts hold) runs until
the last host has committed ``--cut-after`` verdicts and holds another job; then that host's link is taken
down. With ``--mend`` the link comes back once the driver has named the node lost.

Prints the timeline (cluster up, cut, node named lost, lost jobs decided elsewhere), throughput before and
after the cut, and checks: every planned job decided exactly once, every error a ``worker_died`` that names
the lost node, no verdict from that node after the cut, the node named once in the log and in
``events.jsonl``, and nothing left of the hosts afterwards. Exits 1 if a check fails.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # for tests.support: the namespaces and the recipe

import yaml
from pydantic import ValidationError

from scratchworld_dist.results import JobRow, JobStart, NodeLost, RunEvent, RunStore, read_events
from scratchworld_dist.suites import load_suite
from tests.support.netns_cluster import HostCluster
from tests.support.netns_hosts import Host, IsolatedHosts, unavailable

REPO = Path(__file__).resolve().parents[1]
RUNS = "/tmp/runs"
"""Run directories on the driver's own disk (an ``s3://`` URL once runs go to object storage)."""

POLL_S = 0.2
KEY_ENV = "SCRATCHWORLD_LLM_API_KEY"
"""The model's key: in the worker hosts' environment only (where the llm agent calls the model)."""


def held(folder: Path, hostname: str, verdicts: int) -> bool:
    """``hostname`` committed ``verdicts`` verdicts and holds another job."""
    if not (folder / "journal").exists():
        return False
    mine = [row for row in RunStore(folder).job_rows() if row.worker_host == hostname]
    if len(mine) < verdicts:
        return False
    workers = {row.worker_index for row in mine}
    sent = [e for e in events_so_far(folder) if isinstance(e, JobStart) and e.worker in workers]
    return len(sent) > len(mine)


def events_so_far(folder: Path) -> list[RunEvent]:
    """The run's events; none when a line was being written as it was read (the next poll sees it)."""
    try:
        return read_events(folder)
    except ValidationError:
        return []


def llm_sweep(host: Host) -> dict[str, Any]:
    """The llm agent's part of the config, its model a server started on ``host``'s address."""
    model = [sys.executable, str(REPO / "benchmarks" / "_chaos" / "host_model.py"), host.address, str(REPO / "tasks")]
    server = subprocess.Popen(host.command(model, {"PYTHONDONTWRITEBYTECODE": "1"}), stdout=subprocess.PIPE, text=True)
    assert server.stdout is not None
    url = server.stdout.readline().strip()  # the server dies with its host
    if not url.startswith("http://"):
        raise RuntimeError(f"the model server on {host.name} did not start (exit {server.poll()})")
    return {
        "agent": "llm",
        "models": [{
            "model": "openai/replay", "name": "replay", "api_base": url, "api_key_env": KEY_ENV,
            "temperature": 0, "max_tokens": 256,
        }],
        "llm": {"history_messages": 200},
        "episodes": {"modes": ["composite"], "max_steps": 40},
    }  # fmt: skip


def per_minute(rows: list[JobRow], start: float, end: float) -> str:
    done = [row for row in rows if row.outcome != "error" and start <= row.finished_at.timestamp() < end]
    minutes = (end - start) / 60
    return f"{len(done) / minutes:.1f} verdicts/min ({len(done)} in {end - start:.0f} s)" if minutes > 0 else "-"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--agent", choices=("oracle", "llm"), default="oracle")
    parser.add_argument("--tasks", type=int, default=12, help="tasks of our suite (in its order)")
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--workers", type=int, default=2, help="hosts with editors (the last one is cut)")
    parser.add_argument("--slots", type=int, default=1, help="editors per worker host")
    parser.add_argument("--cut-after", type=int, default=2, help="verdicts the cut host delivers first")
    parser.add_argument("--mend", action="store_true", help="restore the link once the node is named lost")
    parser.add_argument("--keep", type=Path, help="copy the run directory and the driver's log here")
    args = parser.parse_args()
    reason = unavailable()
    if reason is not None:
        print(f"error: {reason}", file=sys.stderr)
        return 2

    tasks = [task.id for task in load_suite(REPO / "tasks").tasks][: args.tasks]
    log = Path(tempfile.mkdtemp(prefix="chaos-hosts-")) / "driver.log"
    began = time.monotonic()
    timeline: list[tuple[float, str]] = []

    def mark(what: str) -> None:
        timeline.append((time.monotonic() - began, what))
        print(f"{timeline[-1][0]:7.1f} s  {what}", flush=True)

    checks: list[tuple[bool, str, str]] = []
    hosts = IsolatedHosts(args.workers + 1)
    tag = hosts.tag
    try:
        driver_host, *workers = hosts.hosts
        cut = workers[-1]
        mark(f"{len(hosts.hosts)} hosts made ({', '.join(f'{h.name} {h.address}' for h in hosts.hosts)})")
        cluster = HostCluster(driver_host)
        cluster.head()
        for host in workers:
            cluster.node(host, args.slots, {KEY_ENV: "sk-local"})
        cluster.wait_for(nodes=len(hosts.hosts), browsers=args.slots * len(workers))
        mark(f"cluster up: head on {driver_host.name}, {args.slots} editor(s) on each of {len(workers)} host(s)")

        shutil.copytree(REPO / "tasks", driver_host.path("/tmp/suite"))
        config = {
            "name": "apart", "suite": "/tmp/suite", "agent": "oracle", "tasks": {"ids": tasks}, "seeds": args.seeds,
            "output": f"{RUNS}/apart", "ray": {"address": cluster.address, "connect_timeout_s": 60},
            "limits": {"pages_per_worker": 1, "episode_timeout_s": 300, "retries": 2},
        }  # fmt: skip
        if args.agent == "llm":
            config.update(llm_sweep(driver_host))
            mark(f"model server on {driver_host.name}: {config['models'][0]['api_base']}")
        driver_host.path("/tmp/apart.yaml").write_text(yaml.safe_dump(config))
        folder = driver_host.path(f"{RUNS}/apart")
        driver = cluster.driver("/tmp/apart.yaml", log)
        sweep_began = time.time()
        mark(f"driver started: {len(tasks) * args.seeds} job(s)")
        cut_at: float | None = None
        lost_at: float | None = None
        while driver.poll() is None:
            if cut_at is None and held(folder, cut.name, args.cut_after):
                hosts.cut(cut)
                cut_at = time.time()
                mark(f"{cut.name}'s link down ({cut.address}) after {args.cut_after} verdict(s) from it")
            if cut_at is not None and lost_at is None:
                named = [e for e in events_so_far(folder) if isinstance(e, NodeLost)]
                if named:
                    lost_at = named[0].time.timestamp()
                    mark(f"driver names {cut.name} lost ({lost_at - cut_at:.1f} s after the cut): {named[0].reason}")
                    if args.mend:
                        hosts.mend(cut)
                        mark(f"{cut.name}'s link up again")
            time.sleep(POLL_S)
        sweep_ended = time.time()
        mark(f"driver exited {driver.returncode}")
        if args.keep is not None:
            shutil.copytree(folder, args.keep / "run", dirs_exist_ok=True)
            shutil.copy(log, args.keep / "driver.log")

        rows = RunStore(folder).job_rows()
        out = log.read_text()
        decided = Counter(row.job_id for row in rows if row.outcome != "error")
        planned = len(tasks) * args.seeds
        checks.append((driver.returncode == 0, "the driver exits 0", f"exit {driver.returncode}"))
        checks.append(
            (len(decided) == planned and set(decided.values()) == {1}, "every job decided exactly once",
             f"{len(decided)}/{planned} decided, most verdicts for one job: {max(decided.values(), default=0)}")
        )  # fmt: skip
        errors = [row for row in rows if row.outcome == "error"]
        naming = [row for row in errors if f"node {cut.name} ({cut.address}" in (row.error_message or "")]
        checks.append(
            (cut_at is not None and bool(errors) and len(naming) == len(errors)
             and {row.error_class for row in errors} == {"worker_died"},
             "the cut host's jobs in flight end worker_died, naming its node",
             f"{len(naming)}/{len(errors)} error attempt(s) name it")
        )  # fmt: skip
        late = [row for row in rows if row.worker_host == cut.name and cut_at and row.finished_at.timestamp() > cut_at]
        checks.append((not late, "no verdict from the cut host after the cut", f"{len(late)} row(s)"))
        again = [r for r in rows if r.job_id in {e.job_id for e in errors} and r.outcome != "error"]
        checks.append(
            (len(again) == len({e.job_id for e in errors}) and all(r.worker_host != cut.name for r in again),
             "each lost job decided on another host", ", ".join(f"{r.task_id} on {r.worker_host}" for r in again))
        )  # fmt: skip
        said = [line for line in out.splitlines() if line.startswith("node lost: ")]
        events = [e for e in read_events(folder) if isinstance(e, NodeLost)]
        checks.append(
            (len(said) == 1 and len(events) == 1 and events[0].hostname == cut.name,
             "the lost node is named once in the log and in events.jsonl", said[0] if said else "not said")
        )  # fmt: skip
        hosts_on = Counter(row.worker_host for row in rows if row.outcome != "error")
        print()
        print(f"verdicts by host: {dict(hosts_on)}; error attempts: {len(errors)}")
        if cut_at is not None:
            first_sent = min(row.started_at.timestamp() for row in rows)  # after the workers opened their editors
            print(f"before the cut: {per_minute(rows, first_sent, cut_at)} from the first job sent")
            print(f"after the cut:  {per_minute(rows, cut_at, sweep_ended)}")
            resent = [r for r in again if r.started_at is not None]
            if lost_at is not None:
                print(f"cut -> node named lost: {lost_at - cut_at:.1f} s")
            if resent:
                first = min(r.started_at.timestamp() for r in resent)
                last = max(r.finished_at.timestamp() for r in resent)
                print(f"cut -> lost job(s) started elsewhere: {first - cut_at:.1f} s; decided: {last - cut_at:.1f} s")
        print(f"sweep wall: {sweep_ended - sweep_began:.1f} s")
    finally:
        hosts.close()
        listed = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True).stdout
        left = [h.pid for h in hosts.hosts if Path(f"/proc/{h.pid}").exists()]
        checks.append((tag not in listed and not left, "nothing of the hosts outlives the run", f"tag {tag}"))
        mark("hosts torn down")
    print()
    for ok, name, figures in checks:
        print(f"{'PASS' if ok else 'FAIL'}  {name}: {figures}")
    return 0 if all(ok for ok, _, _ in checks) else 1


if __name__ == "__main__":
    raise SystemExit(main())
