"""Prints what a run directory on object storage costs, against a local S3 API server (moto's, on 127.0.0.1):

    .venv/bin/python benchmarks/remote_storage.py [--seeds 1] [--duration 0.3]

1. Upload lag: for every committed attempt, the time from its local commit (the journal line flushed) to its
   journal entry's object in the bucket, p50/p95/max, while the sweep runs. The sweep is the demo's matrix (our
   12 tasks in both modes, ``--seeds`` seeds) with synthetic (browserless) episodes of ``--duration`` seconds,
   so the uploads compete with the driver's loop as in a real run, but carry no episode artifacts.
2. Resume from remote: a driver on "another machine" (an empty local folder) opening the run: the lease taken,
   the mirror rebuilt from the bucket (manifest, events, shards) and the decided jobs found; and the whole
   ``scratchworld run`` that finds nothing left to do.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from scratchworld_dist import _run  # noqa: E402
from scratchworld_dist.results import RunStore  # noqa: E402
from scratchworld_dist.results.remote._sync import RemoteRun  # noqa: E402
from scratchworld_dist.sweep import sweep_config_from  # noqa: E402
from tests.support.s3_server import S3Server, s3_environment  # noqa: E402


def config(url: str, mirrors: Path, seeds: int, duration: float) -> dict[str, object]:
    return {
        "name": "remote-bench",
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "seeds": seeds,
        "episodes": {"modes": ["composite", "primitive"], "synthetic": {"duration_s": duration}},
        "output": url,
        "storage": {"cache_dir": str(mirrors)},
    }


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q * (len(ordered) - 1)))]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--duration", type=float, default=0.3, help="seconds per synthetic episode")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        server = S3Server(folder / "moto.log")
        try:
            with s3_environment(server):
                url = f"s3://{server.bucket()}/bench/run"
                opened: list[RemoteRun] = []
                real_open = _run.open_remote

                def keep(*given: object) -> RemoteRun | None:
                    remote = real_open(*given)  # type: ignore[arg-type]
                    opened.append(remote)  # type: ignore[arg-type]
                    return remote

                _run.open_remote = keep  # type: ignore[assignment]
                sweep = sweep_config_from(config(url, folder / "machine-a", args.seeds, args.duration), folder)
                started = time.perf_counter()
                summary = _run.run_sweep(sweep)
                wall = time.perf_counter() - started
                lags = opened[0].uploader.lags
                print(f"sweep: {summary.planned} job(s), {summary.sent} attempt(s) in {wall:.1f} s -> {url}")
                print(
                    f"upload lag (commit -> journal entry visible), {len(lags)} entries: "
                    f"p50 {statistics.median(lags) * 1000:.0f} ms, p95 {percentile(lags, 0.95) * 1000:.0f} ms, "
                    f"max {max(lags) * 1000:.0f} ms"
                )
                started = time.perf_counter()
                remote = RemoteRun.open(url, folder / "machine-b", 120, print)
                decided = sum(done for _, done in RunStore(remote.mirror).attempts().values())
                opened_s = time.perf_counter() - started
                remote.close(60)
                print(f"resume from remote (lease, mirror rebuilt, {decided} decided jobs found): {opened_s:.2f} s")
                again = sweep_config_from(config(url, folder / "machine-c", args.seeds, args.duration), folder)
                started = time.perf_counter()
                resumed = _run.run_sweep(again)
                print(
                    f"`run` from an empty folder with nothing left to do ({resumed.already_decided} decided): "
                    f"{time.perf_counter() - started:.2f} s"
                )
        finally:
            server.close()


if __name__ == "__main__":
    main()
