"""Prints what an episode video costs: CPU seconds per wall minute of episode, bytes per episode, and how much
longer an episode takes with video on.

    .venv/bin/python benchmarks/video_cost.py [--tasks 4] [--modes primitive] [--fps 5] [--clock virtual] [--repeat 1]

Each task's episode (the oracle agent, our suite) runs with video off and on, in alternating order, in one
browser with a pool of editors as a worker has. CPU is read for the browser's processes and this process
together (the encoder is a thread of it), from the start of an episode to its verdict; the video's cost is
the difference between the on and off runs of the same episode, per minute of its video. The encoder
thread's own CPU is printed apart (it is measured exactly, the difference is noisy on a shared machine).
Slowdown: the agent's part of the episode (``EpisodeTimings.agent_s``: its steps, and stopping the video),
and the whole episode with its evaluation.
"""

from __future__ import annotations

import argparse
import asyncio
import statistics
import time
from dataclasses import dataclass
from pathlib import Path

import psutil

from scratchworld_dist.kinds.tasks import EpisodeMatrix, TaskContent, plan_jobs, read_task
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import worker_job
from workers.actor import WorkerBrowser
from workers.agent_api import StepResult
from workers.agents import OracleAgent
from workers.contract import Action, ClockMode, EpisodeClock, Mode, Observation, ObservationSettings, RecordSettings
from workers.editor import BrowserSession, EditorPool
from workers.kinds.tasks import EpisodeRunner, EpisodeSpec

SUITE_DIR = Path(__file__).resolve().parents[1] / "tasks"
WIDTH = 1280
"""The video's width (``--width``)."""

THINK_S = 0.0
"""Seconds the agent waits before each action (``--think``), as a model would: the page is still meanwhile."""


class ThinkingOracle(OracleAgent):
    """The oracle, taking ``THINK_S`` before each action as a model-driven agent takes its model's latency."""

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        if THINK_S:
            await asyncio.sleep(THINK_S)
        return await super().act(observation, last)


@dataclass
class Run:
    task: str
    mode: str
    video: bool
    outcome: str
    agent_s: float
    total_s: float
    cpu_s: float
    video_s: float = 0.0
    video_bytes: int = 0
    frames: int = 0
    encode_cpu_s: float = 0.0


def tree_cpu(pid: int) -> float:
    """CPU seconds of a process and all its descendants so far."""
    total = 0.0
    root = psutil.Process(pid)
    for process in [root, *root.children(recursive=True)]:
        try:
            times = process.cpu_times()
        except psutil.Error:
            continue
        total += times.user + times.system
    return total


def spec(content: TaskContent, mode: Mode, clock: ClockMode, record: RecordSettings) -> EpisodeSpec:
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=[mode],
            agent="oracle",
            tasks=[content],
            seeds=[0],
            max_steps=300,
            observation=ObservationSettings(ocr="none"),
            episode_clock=EpisodeClock(mode=clock),
            record=record,
        )
    )
    return worker_job(job, 1, 600)  # type: ignore[return-value]


async def one(
    runner: EpisodeRunner, browser_pid: int, content: TaskContent, mode: Mode, clock: ClockMode, fps: int, video: bool
) -> Run:
    record = RecordSettings(video=video, fps=fps, width=WIDTH)
    before = tree_cpu(browser_pid) + time.process_time()
    result = await runner.run(spec(content, mode, clock, record), content.payload, ThinkingOracle())
    cpu = tree_cpu(browser_pid) + time.process_time() - before
    run = Run(content.task.id, mode, video, result.outcome, result.timings.agent_s, result.timings.total_s, cpu)
    if result.video is not None:
        info = result.video.info
        run.video_s, run.video_bytes, run.frames, run.encode_cpu_s = (
            info.duration_s,
            len(result.video.mp4),
            info.frames,
            info.encode_cpu_s,
        )
    return run


async def main(tasks: int, skip: int, modes: list[Mode], fps: int, clock: ClockMode, repeat: int) -> None:
    suite = load_suite(SUITE_DIR)
    contents = [read_task(task) for task in suite.tasks if task.trajectory() is not None][skip : skip + tasks]
    runs: list[Run] = []
    started = time.perf_counter()
    async with BrowserSession() as session, EditorPool(session, spare=0) as pool:
        runner = EpisodeRunner(WorkerBrowser(session, pool))
        pid = await session.browser_pid()
        for content in contents[:1]:  # warm up: the pool's editors open, V8's code cache fills
            await one(runner, pid, content, modes[0], clock, fps, False)
        for round_ in range(repeat):
            for number, content in enumerate(contents):
                for mode in modes:
                    order = (False, True) if (number + round_) % 2 == 0 else (True, False)
                    for video in order:
                        run = await one(runner, pid, content, mode, clock, fps, video)
                        runs.append(run)
                        shown = f"{run.video_bytes / 1e6:.2f} MB, {run.frames} frames" if video else "no video"
                        print(
                            f"{run.task:<32} {mode:<9} video {'on ' if video else 'off'} {run.outcome:<7} "
                            f"agent {run.agent_s:6.1f} s  total {run.total_s:6.1f} s  cpu {run.cpu_s:6.1f} s  {shown}",
                            flush=True,
                        )
        await runner.browser.close()
    report(runs, fps, clock, time.perf_counter() - started)


def report(runs: list[Run], fps: int, clock: str, wall_s: float) -> None:
    on = [r for r in runs if r.video]
    pairs = [(o, next(f for f in runs if not f.video and (f.task, f.mode) == (o.task, o.mode))) for o in on]
    minutes = sum(o.video_s for o in on) / 60
    extra_cpu = sum(o.cpu_s - f.cpu_s for o, f in pairs)
    same = all(o.outcome == f.outcome for o, f in pairs)
    sizes = [o.video_bytes for o in on]
    agent = [o.agent_s / f.agent_s - 1 for o, f in pairs]
    total = [o.total_s / f.total_s - 1 for o, f in pairs]
    agent_sum = sum(o.agent_s for o, _ in pairs) / sum(f.agent_s for _, f in pairs) - 1
    total_sum = sum(o.total_s for o, _ in pairs) / sum(f.total_s for _, f in pairs) - 1
    mb = [size / 1e6 for size in sizes]
    lines = [
        f"video cost: {len(on)} episode(s) each way, {fps} fps, {WIDTH} px wide, {clock} episode clock, "
        f"{THINK_S:g} s before each action, "
        f"{wall_s / 60:.1f} min in all",
        f"  video recorded: {minutes:.2f} min; outcomes equal with and without: {same}",
        f"  CPU-s per wall minute of episode (on - off, browser + worker): {extra_cpu / minutes:.2f}",
        f"  of which the encoder thread: {sum(o.encode_cpu_s for o in on) / minutes:.2f}",
        f"  bytes per episode: mean {statistics.mean(mb):.2f} MB, median {statistics.median(mb):.2f} MB, "
        f"max {max(mb):.2f} MB ({sum(mb) / minutes:.2f} MB per minute of video)",
        f"  slowdown, agent part: summed {agent_sum:+.1%}, per episode mean {statistics.mean(agent):+.1%}, "
        f"median {statistics.median(agent):+.1%}",
        f"  slowdown, whole episode (evaluation included): summed {total_sum:+.1%}, mean {statistics.mean(total):+.1%}",
    ]
    print("\n" + "\n".join(lines))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tasks", type=int, default=4, help="the first N tasks of our suite with a trajectory")
    parser.add_argument("--skip", type=int, default=0, help="start at the suite's task N+1")
    parser.add_argument("--modes", default="primitive", help="comma-separated: composite,primitive")
    parser.add_argument("--fps", type=int, default=5)
    parser.add_argument("--clock", choices=["virtual", "real"], default="virtual")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--think", type=float, default=0.0, help="seconds before each action, as a model's latency")
    parser.add_argument("--width", type=int, default=RecordSettings().width, help="the video's width (320-1280)")
    args = parser.parse_args()
    WIDTH = args.width
    THINK_S = args.think
    modes = [m for m in args.modes.split(",") if m]
    asyncio.run(main(args.tasks, args.skip, modes, args.fps, args.clock, args.repeat))  # type: ignore[arg-type]
