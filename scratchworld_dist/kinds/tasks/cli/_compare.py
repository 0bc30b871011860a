"""``scratchworld compare``: two systems on the jobs both ran, with a paired interval and test; more than two,
ranked, every pair tested with Holm's correction."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click

from scratchworld_dist.cli._options import RUN_DIR, report_format_option
from scratchworld_dist.cli._output import emit

if TYPE_CHECKING:
    from scratchworld_dist.reports import ReportFormat


@click.command("compare", epilog="Example: scratchworld compare results/a:gpt-4o results/b:gpt-4o-mini --format md")
@click.argument("system_a", metavar="RUN_A[:SYSTEM][@MODE]")
@click.argument("system_b", metavar="RUN_B[:SYSTEM][@MODE]")
@click.argument("more", nargs=-1, metavar="[RUN_C[:SYSTEM][@MODE]...]")
@report_format_option
@click.option("--out", type=click.Path(dir_okay=False, path_type=Path), help="Write here instead of stdout.")
@click.option("--force", is_flag=True, help="Compare runs of different suites, harnesses or conditions anyway.")
@click.option("--resamples", type=click.IntRange(min=100), default=10_000, show_default=True, help="Bootstrap draws.")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the bootstrap's draws.")
@click.option("--alpha", type=click.FloatRange(0, 1, min_open=True, max_open=True), default=0.05, show_default=True,
              help="Family-wise error rate of a ranking's pairwise tests (three systems or more).")  # fmt: skip
@click.option("--stable-only", is_flag=True, help="Judge every job without the tests a compared run marks unstable.")
def compare_command(
    system_a: str,
    system_b: str,
    more: tuple[str, ...],
    fmt: ReportFormat,
    out: Path | None,
    force: bool,
    resamples: int,
    seed: int,
    alpha: float,
    stable_only: bool,
) -> None:
    """Compare system A with system B on the jobs both ran: SR and PSR differences with a
    paired bootstrap 95% interval over tasks, McNemar's exact test, and wins/losses per task.

    SYSTEM is a model label, an agent, or agent/model as `report` names its rows; it may be
    left out when the run holds one. @MODE pairs one mode with another (e.g. a model's
    composite against its primitive jobs); without it jobs are paired within each mode.
    Runs of different suites, harnesses, evaluation profiles or clocks are refused unless --force,
    except a regrade and its source (`scratchworld regrade`): for those the output names the
    regrade's conditions and lists the jobs whose verdict changed.

    With three systems or more: a ranking by SR, and every pair compared as above with McNemar's
    p-values adjusted by Holm's method (family-wise error at --alpha).

    With --stable-only, each job's verdict and PSR are recomputed from its tests without those any compared
    run marks unstable (their verdict can change with frame timing or phase); a job left with no test has no
    verdict. The output names the tests left out and how many verdicts changed.
    """
    from scratchworld_dist.kinds.tasks.report import (  # the statistics stack: when a comparison is made
        compare_runs,
        parse_selector,
        rank_systems,
        render_comparison,
        render_ranking,
    )

    system_a, system_b, *rest = (_read_in_place(text) for text in (system_a, system_b, *more))
    more = tuple(rest)
    if more:
        selectors = [parse_selector(text) for text in (system_a, system_b, *more)]
        ranking = rank_systems(
            selectors, force=force, resamples=resamples, seed=seed, alpha=alpha, stable_only=stable_only
        )
        text = ranking.model_dump_json(indent=2) + "\n" if fmt == "json" else render_ranking(ranking, fmt)
        emit(text, out, ranking.warnings, f"{fmt} ranking")
        return
    comparison = compare_runs(
        parse_selector(system_a),
        parse_selector(system_b),
        force=force,
        resamples=resamples,
        seed=seed,
        stable_only=stable_only,
    )
    emit(render_comparison(comparison, fmt), out, comparison.warnings, f"{fmt} comparison")


def _read_in_place(text: str) -> str:
    """A selector whose run is a URL (``s3://bucket/run:SYSTEM@MODE``) with the URL replaced by the run's local view
    (its shards are read in the bucket); others as given."""
    if "://" not in text:
        return text
    scheme, rest = text.split("://", 1)
    cut = min((i for i in (rest.find(":"), rest.find("@")) if i >= 0), default=len(rest))
    return str(RUN_DIR.convert(f"{scheme}://{rest[:cut]}", None, None)) + rest[cut:]
