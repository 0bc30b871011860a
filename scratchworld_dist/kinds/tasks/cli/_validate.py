"""``scratchworld validate``: goldens must pass, debug initials must fail."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import click
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from scratchworld_dist._console import make_console
from scratchworld_dist._validation import ProjectCheck, TaskValidation, Which, validate_tasks
from scratchworld_dist.cli._options import (
    evaluation_seed_option,
    page_option,
    render_option,
    suite_check_options,
    timing_option,
)
from scratchworld_dist.suites import SuiteStability, Task, known_stability, load_suite, stability_file
from workers.contract import (
    EvalResult,
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    EvaluationTiming,
)

EXIT_INVALID = 1


def _cell(check: ProjectCheck | None) -> str:
    if check is None:
        return "-"
    if check.error:
        return f"[red]error[/red] {escape(check.error.split(':', 1)[0])}"
    colour = "green" if check.success else "yellow"
    return f"[{colour}]{check.passed}/{check.total}[/{colour}] ({check.wall_s:.1f}s)"


UNSTABLE_MARK = "~"
"""Beside a task whose tests include one known to be unstable (listed under the table)."""


def render_table(rows: list[TaskValidation]) -> Table:
    table = Table("task", "category", "golden", "initial", "verdict")
    for row in rows:
        failures, warnings = row.failures(), row.warnings()
        verdict = "[red]" + escape("; ".join(failures)) + "[/red]" if failures else "ok"
        if warnings:
            verdict += " [yellow](" + escape("; ".join(warnings)) + ")[/yellow]"
        task = Text(row.task_id + (f" {UNSTABLE_MARK}" if row.unstable_tests else ""))
        table.add_row(task, row.category, _cell(row.golden), _cell(row.initial), verdict)
    return table


def stability_lines(rows: list[TaskValidation], stability: SuiteStability | None, source: Path) -> list[str]:
    """What the suite's known test stability says of these tasks: its source, then each unstable test."""
    if stability is None:
        return [f"test stability: none known for this suite ({source} is absent; see scratchworld flakes)"]
    unchecked = [row.task_id for row in rows if row.unstable_tests is None]
    lines = [
        f"test stability: {source} (made {stability.made_on}, {stability.clock} clock); "
        f"{len(rows) - len(unchecked)} of {len(rows)} task(s) checked"
        + (f", not checked or changed since: {', '.join(unchecked)}" if unchecked else "")
    ]
    for row in rows:
        for name, note in (row.unstable_tests or {}).items():
            lines.append(f"{UNSTABLE_MARK} {row.task_id} {name!r}: {note}")
    return lines


@click.command("validate", epilog="Example: scratchworld validate tasks --tasks a,b --parallel 2 --json rows.json")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@suite_check_options
@click.option(
    "--clock",
    type=click.Choice(["virtual", "real"]),
    help="Evaluation clock (default: the suite's, virtual for ours and upstream clones).",
)
@render_option
@page_option
@timing_option
@evaluation_seed_option
@click.option("--json", "json_file", type=click.Path(dir_okay=False, path_type=Path), help="Write the rows as JSON.")
def validate_command(
    suite_dir: Path,
    task_ids: list[str] | None,
    task_list: str | None,
    parallel: int,
    profile: EvaluationProfile | None,
    clock: EvaluationClock | None,
    render: EvaluationRender | None,
    page: EvaluationPage | None,
    timing: EvaluationTiming | None,
    seed: int,
    json_file: Path | None,
) -> None:
    """Evaluate every task's golden and initial project in SUITE_DIR.

    Exits 1 when a golden fails or a debug initial passes.
    """
    suite = load_suite(suite_dir, task_list=task_list)
    tasks = suite.select(ids=task_ids)
    stability = known_stability(suite)
    console = make_console(stderr=True)
    conditions = ""
    if tasks:  # a suite's tasks share their defaults
        spec = tasks[0].evaluation_spec(profile, clock, render, timing, page=page)
        conditions = f", profile {spec.profile}, clock {spec.clock}, render {spec.render}, timing {spec.timing}"
        conditions += f", page {spec.page}, seed {seed}"
    for task in tasks:
        need = task.editor_need()
        if need is not None and page != "editor":
            console.print(f"  {task.id} runs in the editor page: its script names {need}", markup=False)
    console.print(
        f"validating {len(tasks)} task(s) of {suite.name} ({suite.kind}) with {parallel} page(s){conditions}",
        markup=False,
    )

    def progress(task: Task, which: Which, result: EvalResult) -> None:
        outcome = result.error.kind if result.error else f"{result.passed}/{result.total}"
        console.print(f"  {task.id} {which}: {outcome} in {result.timings.total_s:.1f}s", markup=False)

    rows = asyncio.run(
        validate_tasks(
            tasks,
            parallel=parallel,
            on_evaluated=progress,
            profile=profile,
            clock=clock,
            render=render,
            timing=timing,
            page=page,
            stability=stability,
            seed=seed,
        )
    )
    out = make_console()
    out.print(render_table(rows))
    for line in stability_lines(rows, stability, stability_file(suite)):
        out.print(line, markup=False, soft_wrap=True)
    if json_file is not None:
        json_file.write_text(json.dumps([row.model_dump() for row in rows], indent=2) + "\n", encoding="utf-8")
    invalid = [row for row in rows if row.failures()]
    if invalid:
        console.print(f"[red]{len(invalid)} of {len(rows)} task(s) invalid[/red]")
        raise click.exceptions.Exit(EXIT_INVALID)
    console.print(f"all {len(rows)} task(s) valid")
