"""``scratchworld audit SUITE_DIR``: how good a suite's graders are, by mutants and refactorings of its goldens."""

from __future__ import annotations

import json
import re
from pathlib import Path

import click

from scratchworld_dist.cli._options import address_option


@click.command("audit", epilog="Example: scratchworld audit ../scratchworld-upstream --tasks a,b --mutants-per-task 20")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@click.option("--tasks", multiple=True, help="Audit these task ids (comma-separated or repeated; default: all).")
@click.option("--mutants-per-task", type=click.IntRange(min=1), help="At most N mutants per task (default: all).")
@click.option("--refactorings-per-task", type=click.IntRange(min=0), help="At most N refactorings per task.")
@click.option("--seed", type=int, default=0, show_default=True, help="Which mutants a cap picks.")
@click.option(
    "--explanations",
    type=click.Path(dir_okay=False, path_type=Path),
    help="One file of the suite's declarations (answer domains, explained holes) for every task "
    "(default: each task's audit.yaml; for an upstream clone, configs/audit/upstream.yaml).",
)
@click.option(
    "--out", type=click.Path(file_okay=False, path_type=Path), help="Run directory (default: results/audit-<suite>)."
)
@click.option(
    "--json", "json_out", type=click.Path(dir_okay=False, path_type=Path), help="Also write per-task figures here."
)
@address_option
def audit_command(
    suite_dir: Path,
    tasks: tuple[str, ...],
    mutants_per_task: int | None,
    refactorings_per_task: int | None,
    seed: int,
    explanations: Path | None,
    out: Path | None,
    json_out: Path | None,
    address: str | None,
) -> None:
    """Evaluate mutants and refactorings of each task's golden with the task's own tests (a sweep of kind
    ``audit``: run it again to resume), then print the audit report (also RUN_DIR/report.md)."""
    from scratchworld_dist._run import run_sweep  # imports Ray: only for this command
    from scratchworld_dist.kinds.audit._report import AuditReport
    from scratchworld_dist.reports import report_data, report_runs
    from scratchworld_dist.sweep import SweepOverrides, sweep_config_from

    name = "audit-" + (re.sub(r"[^A-Za-z0-9._-]+", "-", suite_dir.resolve().name).strip("-") or "suite")
    section: dict[str, object] = {"seed": seed}
    if mutants_per_task is not None:
        section["mutants_per_task"] = mutants_per_task
    if refactorings_per_task is not None:
        section["refactorings_per_task"] = refactorings_per_task
    if explanations is not None:
        section["explanations"] = str(explanations.resolve())
    data: dict[str, object] = {"name": name, "benchmark": "audit", "suite": str(suite_dir), "audit": section}
    data["output"] = str(out if out is not None else Path("results") / name)
    if address is not None:
        data["ray"] = {"address": address}
    config = sweep_config_from(data, Path.cwd(), changes=SweepOverrides(tasks=list(tasks)))
    summary = run_sweep(config)
    text, _ = report_runs([summary.run_dir], "md")
    (summary.run_dir / "report.md").write_text(text, encoding="utf-8")
    click.echo(text)
    if json_out is not None:
        report = report_data([summary.run_dir])
        assert isinstance(report, AuditReport)
        figures = [
            {
                "task_id": task.task_id, "mutants": task.mutants, "killed": task.killed,
                "equivalent": task.equivalent, "outside_task": task.outside_task,
                "holes": task.holes + task.survived, "explained": task.explained, "vacuous": task.vacuous,
                "refactorings": task.refactorings, "brittle": task.brittle, "errors": task.errors,
            }
            for task in report.tasks
        ]  # fmt: skip
        json_out.write_text(json.dumps(figures, indent=2) + "\n", encoding="utf-8")
