"""``scratchworld evaluate``: one project against one task."""

from __future__ import annotations

import asyncio
from pathlib import Path

import click
from rich.console import Console
from rich.table import Table

from scratchworld_dist.suites import load_suite
from workers import BrowserSession, EvalResult, EvaluationClock, EvaluationProfile, Evaluator

EXIT_NOT_PASSED = 1
EXIT_NO_VERDICT = 3


async def _evaluate(
    project: bytes, suite_dir: Path, task_id: str, profile: EvaluationProfile | None, clock: EvaluationClock | None
) -> EvalResult:
    task = load_suite(suite_dir).task(task_id)
    spec = task.evaluation_spec(profile, clock)
    async with BrowserSession() as session:
        return await Evaluator(session).evaluate(project, spec)


def render_result(result: EvalResult, console: Console) -> None:
    table = Table("test", "passed", "note")
    for test in result.tests:
        table.add_row(test.name, "yes" if test.passed else "no", test.error or "")
    if result.tests:
        console.print(table)
    if result.conditions is not None:
        c = result.conditions
        console.print(
            f"profile {c.profile}: stage canvas {c.stage_canvas[0]}x{c.stage_canvas[1]}, mouse known {c.mouse_known}; "
            f"clock {c.clock}"
        )
    if result.error:
        console.print(f"[red]no verdict[/red] ({result.error.kind}): {result.error.message}")
    else:
        console.print(
            f"passed {result.passed}/{result.total} (PSR {result.psr:.2f}): {'SUCCESS' if result.success else 'FAIL'}"
        )
    for warning in result.warnings:
        console.print(f"[yellow]warning[/yellow]: {warning}")


@click.command("evaluate")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@click.argument("task_id")
@click.argument("project", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option(
    "--json", "json_file", type=click.Path(dir_okay=False, path_type=Path), help="Write the EvalResult as JSON."
)
@click.option("--profile", type=click.Choice(["native", "upstream"]), help="Evaluation profile (default: the suite's).")
@click.option("--clock", type=click.Choice(["virtual", "real"]), help="Evaluation clock (default: the suite's).")
def evaluate_command(
    suite_dir: Path,
    task_id: str,
    project: Path,
    json_file: Path | None,
    profile: EvaluationProfile | None,
    clock: EvaluationClock | None,
) -> None:
    """Evaluate PROJECT (.sb3) against TASK_ID of the suite in SUITE_DIR.

    Exit status: 0 all tests passed, 1 some failed, 3 no verdict (the evaluation itself failed).
    """
    result = asyncio.run(_evaluate(project.read_bytes(), suite_dir, task_id, profile, clock))
    render_result(result, Console())
    if json_file is not None:
        json_file.write_text(result.model_dump_json(indent=2) + "\n", encoding="utf-8")
    if result.error is not None:
        raise click.exceptions.Exit(EXIT_NO_VERDICT)
    if not result.success:
        raise click.exceptions.Exit(EXIT_NOT_PASSED)
