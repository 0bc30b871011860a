"""Calibrates the virtual clock's frame timing on this machine and prints how well it matches Chromium.

    .venv/bin/python benchmarks/frame_lateness.py [--seconds 4] [--upstream DIR] [--limit N] [--write]

Each project (our suite's goldens in ``tasks/``, and the upstream goldens in ``--upstream`` when that
folder exists) runs from the green flag for ``--seconds`` on the REAL clock while the page traces every
VM frame: its start on the real clock, the block functions it called and whether it asked for a
redraw. A frame's lateness is the real time to the next frame minus the nominal 33 ms; the model
``lateness = a + b * blocks + c * redraw`` is fitted over all frames by least squares with no
coefficient below 0 (``scipy.optimize.nnls``). Each project then runs the same simulated seconds in
virtual time, ideal and calibrated, and the table compares frames per second. ``--write`` stores the fit in
``workers/contract/frame_timing.json`` (the default of upstream evaluations in virtual time).
"""

from __future__ import annotations

import argparse
import asyncio
import datetime
import itertools
import os
import platform
import statistics
from pathlib import Path

import numpy as np
from scipy.optimize import nnls

from scratchworld_dist import load_suite
from workers.contract import (
    EvaluationClock,
    EvaluationProfile,
    EvaluationSpec,
    FrameLateness,
    FrameTimingCalibration,
)
from workers.contract._frame_timing import CALIBRATION_FILE
from workers.contract._perturbation import VM_FRAME_MS
from workers.editor import BrowserSession, EditorPool
from workers.evaluation import apply_profile

REPO = Path(__file__).resolve().parents[1]
SCRIPT = Path(__file__).with_name("_frame_lateness") / "green_flag.js"
UPSTREAM = Path("/work/shared/scratchworld-upstream/scratch-gui/static")
SKIP_FRAMES = 2
"""Frames right after the green flag (project start-up work) left out of the fit."""

Frame = tuple[float, float, int, int]


def spec(
    profile: EvaluationProfile, clock: EvaluationClock, seconds: float, lateness: FrameLateness | None
) -> EvaluationSpec:
    return EvaluationSpec(
        script_name=SCRIPT.name,
        script_source=SCRIPT.read_text(encoding="utf-8"),
        timeout_s=seconds + 30,
        profile=profile,
        clock=clock,
        timing="calibrated" if lateness else "ideal",
        frame_lateness=lateness,
        config={"seconds": seconds},
    )


def fps(frames: list[Frame], column: int) -> float:
    """Frames per second on the given clock column (0: page clock, 1: real clock)."""
    used = frames[SKIP_FRAMES:]
    span = used[-1][column] - used[0][column]
    return 1000 * (len(used) - 1) / span if span > 0 else float("nan")


async def trace(pool: EditorPool, project: bytes, run_spec: EvaluationSpec) -> list[Frame]:
    async with pool.editor() as editor:
        await apply_profile(editor, run_spec.profile)
        await editor.load_project(project)
        run = await editor.run_evaluation(run_spec, trace_frames=True)
    if not run.frames or len(run.frames) < SKIP_FRAMES + 3:
        raise RuntimeError(f"too few frames traced ({len(run.frames or [])})")
    return [tuple(frame) for frame in run.frames]  # type: ignore[misc]


def fit(traces: list[list[Frame]]) -> tuple[FrameLateness, int]:
    """Least squares of (real interval to the next frame - 33 ms) on [1, blocks, redraw], with every
    coefficient at least 0 (``scipy.optimize.nnls``): work never makes a frame come early."""
    rows, late = [], []
    for frames in traces:
        used = frames[SKIP_FRAMES:]
        for frame, following in itertools.pairwise(used):
            rows.append((1.0, frame[2], frame[3]))
            late.append(following[1] - frame[1] - VM_FRAME_MS)
    coefficients, _ = nnls(np.array(rows), np.array(late))
    a, b, c = (float(x) for x in coefficients)
    return FrameLateness(fixed_ms=round(a, 4), per_block_ms=round(b, 6), per_redraw_ms=round(c, 4)), len(rows)


def projects(upstream: Path, limit: int | None) -> list[tuple[str, EvaluationProfile, Path]]:
    found: list[tuple[str, EvaluationProfile, Path]] = [
        (task.id, "native", task.golden_project) for task in load_suite(REPO / "tasks").select() if task.golden_project
    ]
    if upstream.is_dir():
        found += [
            (path.stem.removesuffix("_golden"), "upstream", path) for path in sorted(upstream.glob("*_golden.sb3"))
        ]
    return found[:limit] if limit else found


async def main(seconds: float, upstream: Path, limit: int | None, write: bool) -> None:
    chosen = projects(upstream, limit)
    load = os.getloadavg()[0]
    print(f"{len(chosen)} project(s), {seconds:g} s each; load average {load:.1f}", flush=True)
    real: dict[str, list[Frame]] = {}
    async with BrowserSession() as session, EditorPool(session, spare=0) as pool:
        for name, profile, path in chosen:
            try:
                real[name] = await trace(pool, path.read_bytes(), spec(profile, "real", seconds, None))
            except Exception as exc:  # a project that does not run is reported and left out
                print(f"{name}: no real trace ({type(exc).__name__}: {exc})", flush=True)
        lateness, used = fit(list(real.values()))
        print(f"fit over {used} frames: {lateness}", flush=True)
        print(f"{'project':48} {'profile':8} {'real':>6} {'ideal':>6} {'calib.':>6}  (frames per second)")
        rows: list[dict[str, str | float]] = []
        for name, profile, path in chosen:
            if name not in real:
                continue
            data = path.read_bytes()
            ideal = await trace(pool, data, spec(profile, "virtual", seconds, None))
            calibrated = await trace(pool, data, spec(profile, "virtual", seconds, lateness))
            row = {
                "project": name,
                "real": fps(real[name], 1),
                "ideal": fps(ideal, 0),
                "calibrated": fps(calibrated, 0),
            }
            rows.append(row)
            print(
                f"{name[:48]:48} {profile:8} {row['real']:6.2f} {row['ideal']:6.2f} {row['calibrated']:6.2f}",
                flush=True,
            )
    for variant in ("ideal", "calibrated"):
        errors = [abs(float(row[variant]) - float(row["real"])) / float(row["real"]) for row in rows]
        print(f"{variant}: mean absolute error {100 * statistics.mean(errors):.1f} % of the real frame rate")
    if write:
        calibration = FrameTimingCalibration(
            lateness=lateness,
            measured_on=datetime.date.today().isoformat(),
            machine={
                "cpu": platform.processor() or platform.machine(),
                "cores": os.cpu_count() or 0,
                "load_average": round(load, 1),
                "seconds_per_project": seconds,
            },
            method="non-negative least squares (scipy.optimize.nnls) of real interval - 33 ms on [1, blocks, redraw]",
            frames=used,
            projects=[{k: round(v, 2) if isinstance(v, float) else v for k, v in row.items()} for row in rows],
        )
        CALIBRATION_FILE.write_text(calibration.model_dump_json(indent=1) + "\n", encoding="utf-8")
        print(f"wrote {CALIBRATION_FILE.relative_to(REPO)}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=4.0)
    parser.add_argument("--upstream", type=Path, default=UPSTREAM)
    parser.add_argument("--limit", type=int, default=None)
    parser.add_argument("--write", action="store_true")
    args = parser.parse_args()
    asyncio.run(main(args.seconds, args.upstream, args.limit, args.write))
