"""``scratchworld perception``: the visual perception benchmark's own tools (running it is ``scratchworld run``
with ``benchmark: perception``)."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import TYPE_CHECKING

import click

from scratchworld_dist.cli._options import id_list_option

if TYPE_CHECKING:
    from scratchworld_dist.kinds.perception.items import PerceptionView

EXIT_INVALID = 1


@click.group("perception", epilog="Example: scratchworld perception make projects/*.sb3 --out perception-items")
def perception_group() -> None:
    """Perception items: generate a suite from projects, validate a suite in this editor."""


@perception_group.command("make", epilog="Example: scratchworld perception make projects/*.sb3 --out perception-items")
@click.argument("projects", nargs=-1, required=True, type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--out", required=True, type=click.Path(file_okay=False, path_type=Path), help="New suite folder.")
@click.option("--name", default=None, help="Suite name (default: the folder's name).")
@click.option("--per-view", type=click.IntRange(min=1), default=8, show_default=True, help="Items at most per view.")
@click.option("--max-views", type=click.IntRange(min=1), default=None, help="Views at most (default: all).")
@click.option("--seed", type=int, default=0, show_default=True, help="Seed of the values asked and the selection.")
def make_command(
    projects: tuple[Path, ...], out: Path, name: str | None, per_view: int, max_views: int | None, seed: int
) -> None:
    """Make perception items from PROJECTS (.sb3), with answers from the editor itself.

    Each target with scripts is shown in a real editor: plainly, scrolled to cut a script at the edge,
    and with a stack pulled off, a script laid over another and a reporter left beside its slot. Every
    question a view settles beyond doubt is a candidate; a balanced set (YES as often as NO in each
    kind) is written with the screenshots and saved projects.
    """
    from scratchworld_dist.kinds.perception.items import (
        make_perception_suite,  # the browser stack, for this command only
    )

    def shown(view: PerceptionView, count: int) -> None:
        click.echo(f"  {view.id}: {count} candidate(s)", err=True)

    made = asyncio.run(
        make_perception_suite(
            list(projects),
            out,
            name=name or out.name,
            per_view=per_view,
            max_views=max_views,
            seed=seed,
            on_problem=lambda message: click.echo(f"left out: {message}", err=True),
            on_view=shown,
        )
    )
    per_item = made.seconds / made.items if made.items else 0.0
    click.echo(
        f"wrote {made.items} item(s) about {made.views} view(s) (of {made.views_shown} shown, {made.candidates} "
        f"candidates) to {made.root} in {made.seconds:.0f} s ({per_item:.2f} s per item)"
    )
    for key, count in made.composition.items():
        click.echo(f"  {key}: {count}")


@perception_group.command("validate", epilog="Example: scratchworld perception validate perception-items --views a,b")
@click.argument("suite_dir", type=click.Path(file_okay=False, path_type=Path))
@id_list_option("--views", "view_ids", help="View ids, comma-separated or repeated (default: all).")
@click.option("--parallel", type=click.IntRange(min=1), default=1, show_default=True, help="Editors at a time.")
def validate_command(suite_dir: Path, view_ids: list[str] | None, parallel: int) -> None:
    """Re-derive every item of SUITE_DIR (a suite made by `perception make`) from its saved project, here.

    Each view's project is shown again at its view, its facts collected again, and every item's answer and
    question derived again from its fact. Exits 1 naming each item that differs or cannot be derived. The
    share of pixels of a new screenshot that differ from the stored one is printed for information.
    """
    from scratchworld_dist._console import make_console  # rich: for this command only
    from scratchworld_dist.kinds.perception.items import (
        ViewCheck,
        load_perception_suite,
        refuse_upstream,
        validate_perception_suite,
    )

    suite = load_perception_suite(suite_dir)
    refuse_upstream(suite)
    wanted = view_ids
    if wanted is not None:
        for view_id in wanted:
            suite.view(view_id)  # an unknown view is a one-line error
    console = make_console(stderr=True)
    for problem in suite.problems:
        console.print(f"left out: {problem}", markup=False)
    count = len(wanted) if wanted is not None else len(suite.views)
    console.print(f"validating {count} view(s) of {suite.name} with {parallel} editor(s)", markup=False)

    def progress(check: ViewCheck) -> None:
        pixels = "-" if check.pixels_differing is None else f"{check.pixels_differing:.3%}"
        bad = [item for item in check.items if not item.valid]
        verdict = f"{len(check.items) - len(bad)} of {len(check.items)} item(s) hold"
        measured = f"{check.blocks} blocks measured in {check.facts_ms:.0f} ms" if check.facts_ms is not None else "-"
        line = f"  {check.view}: {verdict}; pixels differing {pixels}; {measured}; {check.seconds:.1f} s"
        console.print(line, markup=False)
        for item in bad:
            console.print(f"    INVALID {item.item_id}: {item.problem}", markup=False)

    checks = asyncio.run(validate_perception_suite(suite, editors=parallel, views=wanted, on_checked=progress))
    items = [item for check in checks for item in check.items]
    invalid = [item for item in items if not item.valid]
    if invalid or suite.problems:
        console.print(f"{len(invalid)} of {len(items)} item(s) invalid", markup=False)
        raise click.exceptions.Exit(EXIT_INVALID)
    console.print(f"all {len(items)} item(s) of {len(checks)} view(s) valid", markup=False)
