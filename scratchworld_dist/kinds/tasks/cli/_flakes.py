"""``scratchworld flakes``: which tests change their verdict under perturbations that must not change it."""

from __future__ import annotations

import asyncio
import os
import shlex
import sys
from pathlib import Path

import click
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from scratchworld_dist._console import make_console
from scratchworld_dist.cli._options import comma_list, page_option, render_option, suite_check_options
from scratchworld_dist.kinds.tasks.flakes import (
    AXES,
    DEFAULT_LATENESS_MS,
    Axis,
    FlakeConditions,
    FlakeReport,
    FlakeRun,
    FlakeSettings,
    TestStability,
    plan_variants,
    run_flakes,
    stability_of_tests,
    suite_stability,
)
from scratchworld_dist.suites import default_timing, load_suite
from workers.contract import EvaluationClock, EvaluationPage, EvaluationProfile, EvaluationRender

EXIT_UNSTABLE = 1
MAX_FLIPS_SHOWN = 3


def _flips(row: TestStability) -> str:
    shown = [f"{flip.label} → {flip.verdict}" for flip in row.flips[:MAX_FLIPS_SHOWN]]
    if len(row.flips) > MAX_FLIPS_SHOWN:
        shown.append(f"+{len(row.flips) - MAX_FLIPS_SHOWN} more")
    return "; ".join(shown)


def render_table(rows: list[TestStability]) -> Table:
    table = Table("task", "project", "test", "baseline", "stability", "flipped by", "passes at")
    for row in rows:
        if row.stable:
            stability = "[green]stable[/green]"
        else:
            colour = "red" if row.blocking else "yellow"
            stability = f"[{colour}]{row.flipped}/{row.runs - 1} ({row.rate:.0%})[/{colour}]"
        table.add_row(
            Text(row.task_id),
            row.which,
            Text(row.test),
            row.baseline,
            stability,
            Text(_flips(row)),
            Text(row.lateness_band.describe() if row.lateness_band else "-"),
        )
    return table


def _axes(text: str) -> tuple[Axis, ...]:
    names = comma_list(text) or []
    unknown = [name for name in names if name not in AXES]
    if unknown or not names:
        raise click.BadParameter(f"{', '.join(unknown) or 'none given'}; choose from {', '.join(AXES)}")
    return tuple(name for name in AXES if name in names)  # type: ignore[misc]


def _levels(text: str) -> tuple[float, ...]:
    try:
        levels = tuple(float(part) for part in comma_list(text) or [])
    except ValueError:
        raise click.BadParameter(f"{text!r} is not a comma-separated list of milliseconds") from None
    if not levels or any(not 0 <= level <= 1000 for level in levels):
        raise click.BadParameter("give one or more levels from 0 to 1000 ms")
    return levels


@click.command("flakes", epilog="Example: scratchworld flakes tasks --tasks a --tasks b --runs 3 --json flakes.json")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@suite_check_options
@click.option(
    "--clock",
    type=click.Choice(["virtual", "real"]),
    help="Baseline clock (default: the suite's); the clock axis runs the other one.",
)
@render_option
@page_option
@click.option(
    "--runs", type=click.IntRange(1, 50), default=3, show_default=True, help="Runs per axis with drawn values."
)
@click.option("--axes", default=",".join(AXES), show_default=True, help="Perturbations to vary, comma-separated.")
@click.option(
    "--lateness",
    default=",".join(f"{ms:g}" for ms in DEFAULT_LATENESS_MS),
    show_default=True,
    help="Timer lateness levels in ms (virtual clock) for the frame-rate band.",
)
@click.option("--seed", type=click.IntRange(min=0), default=0, show_default=True, help="Seed of every drawn value.")
@click.option(
    "--load-processes",
    type=click.IntRange(1, 64),
    help="Busy processes during the load runs (default: one per CPU).",
)
@click.option("--json", "json_file", type=click.Path(dir_okay=False, path_type=Path), help="Write the report as JSON.")
@click.option(
    "--stability-out",
    type=click.Path(dir_okay=False, path_type=Path),
    help="Write what was found as the suite's known test stability (see docs/evaluation.md), replacing that file.",
)
def flakes_command(
    suite_dir: Path,
    task_ids: list[str] | None,
    task_list: str | None,
    parallel: int,
    profile: EvaluationProfile | None,
    clock: EvaluationClock | None,
    render: EvaluationRender | None,
    page: EvaluationPage | None,
    runs: int,
    axes: str,
    lateness: str,
    seed: int,
    load_processes: int | None,
    json_file: Path | None,
    stability_out: Path | None,
) -> None:
    """Evaluate every golden and initial in SUITE_DIR under perturbations that must not change a verdict.

    Each axis is varied alone from a baseline run; a test whose verdict differs in any run is
    unstable. Exits 1 when a test of a golden or of a debug task's initial is unstable.
    """
    settings = FlakeSettings(
        runs=runs,
        axes=_axes(axes),
        lateness_ms=_levels(lateness),
        seed=seed,
        load_processes=load_processes or os.cpu_count() or 1,
    )
    suite = load_suite(suite_dir, task_list=task_list)
    tasks = suite.select(ids=task_ids)
    console = make_console(stderr=True)
    if not tasks:
        raise click.UsageError(f"{suite_dir} has no tasks to check")
    spec = tasks[0].evaluation_spec(profile, clock, render, page=page)  # a suite's tasks share their defaults
    conditions = FlakeConditions(profile=spec.profile, clock=spec.clock, render=spec.render, page=spec.page)
    variants = plan_variants(settings, spec.clock, spec.render, default_timing(spec.profile, "virtual"))
    projects = sum(2 if task.golden_project else 1 for task in tasks)
    console.print(
        f"checking {len(tasks)} task(s) of {suite.name} ({projects} projects x {len(variants)} runs) "
        f"with {parallel} page(s), profile {spec.profile}, clock {spec.clock}, render {spec.render}, page {spec.page}, "
        f"axes {','.join(settings.axes)}",
        markup=False,
    )

    def progress(run: FlakeRun) -> None:
        verdict = run.error.split(":", 1)[0] if run.error else f"{sum(run.verdicts.values())}/{len(run.verdicts)}"
        console.print(
            f"  {run.task_id} {run.which} [{run.variant.label}]: {verdict} in {run.wall_s:.1f}s", markup=False
        )

    done = asyncio.run(run_flakes(tasks, variants, profile=spec.profile, page=page, parallel=parallel, on_run=progress))
    rows = stability_of_tests(done)
    unstable = [row for row in rows if not row.stable]
    blocking = [row for row in unstable if row.blocking]
    out = make_console()
    out.print(render_table(rows))
    for row in unstable:  # one line each, whole, whatever the table had to wrap
        out.print(
            f"unstable: {row.task_id} {row.which} {row.test!r}: {row.flipped}/{row.runs - 1} runs ({row.rate:.0%}): "
            + "; ".join(f"{flip.label} → {flip.verdict}" for flip in row.flips),
            markup=False,
            soft_wrap=True,
        )
    for row in rows:  # the lateness model changes these verdicts (ideal at 0 ms vs calibrated)
        if row.lateness_band is not None and row.lateness_band.depends_on_timing:
            out.print(
                f"depends on frame timing: {row.task_id} {row.which} {row.test!r}: "
                f"{row.lateness_band.calibrated} under calibrated timing",
                markup=False,
                soft_wrap=True,
            )
    report = FlakeReport(
        suite=suite.name,
        conditions=conditions,
        settings=settings,
        evaluations=len(done),
        unstable=len(unstable),
        blocking=len(blocking),
        tests=rows,
        runs=done,
    )
    if json_file is not None:
        json_file.write_text(report.model_dump_json(indent=2) + "\n", encoding="utf-8")
    if stability_out is not None:
        command = shlex.join(["scratchworld", *sys.argv[1:]])
        found = suite_stability(report, tasks, command)
        stability_out.write_text(found.model_dump_json(indent=2) + "\n", encoding="utf-8")
        console.print(f"known test stability of {len(found.scripts)} task(s) written to {stability_out}", markup=False)
    summary = f"{len(unstable)} of {len(rows)} test(s) unstable over {len(done)} evaluation(s)"
    if blocking:
        console.print(f"[red]{escape(summary)}; {len(blocking)} in goldens or debug initials[/red]")
        raise click.exceptions.Exit(EXIT_UNSTABLE)
    console.print(escape(summary) + (" (none in goldens or debug initials)" if unstable else ""))
