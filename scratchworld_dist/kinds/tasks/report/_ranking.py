"""``compare`` of more than two systems: a ranking by SR with every pair tested, corrected for the number of
pairs by Holm's step-down method (family-wise error at ``alpha``; more powerful than Bonferroni and valid
under any dependence between the tests). Each pair is the two-system comparison: the jobs both ran, the
paired bootstrap interval of the SR difference, McNemar's exact test.

Holm's adjustment is eight lines (sort, scale by the number of hypotheses left, keep the running maximum):
SciPy has no Holm (only Benjamini-Hochberg), and statsmodels, which has, would be a large dependency for it.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import combinations

from pydantic import BaseModel

from scratchworld_dist.kinds.tasks.report._compare import Selector, _system, compare_loaded
from scratchworld_dist.kinds.tasks.report._stable_only import (
    StableOnly,
    StableSide,
    left_out_tests,
    stable_only_note,
    stable_only_text,
    stable_verdicts,
)
from scratchworld_dist.kinds.tasks.report._summary import DETERMINATE
from scratchworld_dist.reports import (
    Block,
    Heading,
    Interval,
    LaterFields,
    Paragraph,
    Table,
    blocks_html,
    blocks_markdown,
    html_page,
    load_run,
)


class RankedSystem(BaseModel):
    rank: int
    label: str
    run_dir: str
    mode: str | None
    jobs: int
    determinate: int
    sr: float | None
    """passed / determinate over all of the system's jobs (each pair below uses the jobs both ran)."""


class PairTest(BaseModel):
    a: str
    b: str
    paired_jobs: int
    sr_difference: float | None
    interval: Interval | None
    p_value: float
    """McNemar's exact two-sided p-value of the pair."""

    p_holm: float
    """The p-value adjusted by Holm's method over every pair of the ranking."""

    significant: bool
    """``p_holm < alpha``."""


class Ranking(LaterFields):
    later_fields = ("stable_only",)

    systems: list[RankedSystem]
    pairs: list[PairTest]
    alpha: float
    warnings: list[str]
    stable_only: StableOnly | None = None
    """Set with ``--stable-only``: the tests left out (those any ranked run marks unstable) and, per system,
    the verdicts that changed; every SR and pair above is computed without them."""


def holm(p_values: Sequence[float]) -> list[float]:
    """Holm-adjusted p-values, in the order given: the k-th smallest is scaled by (m - k), then made monotone."""
    m = len(p_values)
    order = sorted(range(m), key=lambda i: p_values[i])
    adjusted = [0.0] * m
    running = 0.0
    for k, i in enumerate(order):
        running = max(running, min(1.0, (m - k) * p_values[i]))
        adjusted[i] = running
    return adjusted


def rank_systems(
    selectors: Sequence[Selector],
    *,
    force: bool = False,
    resamples: int = 10_000,
    seed: int = 0,
    alpha: float = 0.05,
    stable_only: bool = False,
) -> Ranking:
    """Rank the systems ``selectors`` name by SR and test every pair (``RunDirError`` as ``compare_runs``);
    ``stable_only``: without the tests any of the runs marks unstable, the same tests for every system."""
    runs = [load_run(selector.path) for selector in selectors]
    left_out = left_out_tests(runs) if stable_only else None
    systems = []
    sides: list[StableSide] = []
    for run, selector in zip(runs, selectors, strict=True):
        rows, info = _system(run, selector)
        if left_out is not None:
            rows, side = stable_verdicts(run, rows, left_out, info.label + (f"@{info.mode}" if info.mode else ""))
            sides.append(side)
        determinate = [row for row in rows if row.outcome in DETERMINATE]
        passed = sum(row.outcome == "passed" for row in determinate)
        sr = passed / len(determinate) if determinate else None
        systems.append((info, len(determinate), sr))
    comparisons = [
        (
            i,
            j,
            compare_loaded(
                runs[i],
                selectors[i],
                runs[j],
                selectors[j],
                force=force,
                resamples=resamples,
                seed=seed,
                left_out=left_out,
            ),
        )
        for i, j in combinations(range(len(selectors)), 2)
    ]
    adjusted = holm([c.mcnemar.p_value for _, _, c in comparisons])
    pairs = [
        PairTest(
            a=systems[i][0].label,
            b=systems[j][0].label,
            paired_jobs=c.paired_jobs,
            sr_difference=c.sr.difference if c.sr else None,
            interval=c.sr.interval if c.sr else None,
            p_value=c.mcnemar.p_value,
            p_holm=p,
            significant=p < alpha,
        )
        for (i, j, c), p in zip(comparisons, adjusted, strict=True)
    ]
    order = sorted(range(len(systems)), key=lambda k: -(systems[k][2] if systems[k][2] is not None else -1.0))
    ranked = [
        RankedSystem(
            rank=rank,
            label=systems[k][0].label,
            run_dir=systems[k][0].run_dir,
            mode=systems[k][0].mode,
            jobs=systems[k][0].jobs,
            determinate=systems[k][1],
            sr=systems[k][2],
        )
        for rank, k in enumerate(order, start=1)
    ]
    warnings = sorted({w for _, _, c in comparisons for w in c.warnings})
    stable = stable_only_note(runs, left_out, sides) if left_out is not None else None
    return Ranking(systems=ranked, pairs=pairs, alpha=alpha, warnings=warnings, stable_only=stable)


def render_ranking(ranking: Ranking, fmt: str) -> str:
    """The ranking as Markdown, or as an HTML page of the same tables."""
    blocks = ranking_blocks(ranking)
    return html_page(blocks_html(blocks)) if fmt == "html" else blocks_markdown(blocks)


def _pct(value: float | None) -> str:
    return "-" if value is None else f"{100 * value:.1f}%"


def ranking_blocks(ranking: Ranking) -> list[Block]:
    systems = Table(
        header=["rank", "system", "mode", "jobs", "with verdict", "SR"],
        rows=[
            [str(s.rank), f"{s.label} ({s.run_dir})", s.mode or "each", str(s.jobs), str(s.determinate), _pct(s.sr)]
            for s in ranking.systems
        ],
    )
    pairs = []
    for p in ranking.pairs:
        interval = f"[{100 * p.interval.low:+.1f}, {100 * p.interval.high:+.1f}]" if p.interval else "-"
        difference = "-" if p.sr_difference is None else f"{100 * p.sr_difference:+.1f} pts"
        significant = "yes" if p.significant else "no"
        pairs.append(
            [p.a, p.b, str(p.paired_jobs), difference, interval, f"{p.p_value:.4g}", f"{p.p_holm:.4g}", significant]
        )
    return [
        Heading(level=1, text="Ranking"),
        *([Paragraph(text=stable_only_text(ranking.stable_only))] if ranking.stable_only is not None else []),
        systems,
        Paragraph(
            text=f"Every pair on the jobs both ran: SR difference A - B with its paired bootstrap 95% interval, "
            f"McNemar's exact p-value, and that p-value adjusted by Holm's method over the {len(ranking.pairs)} "
            f"pairs (significant: adjusted p < {ranking.alpha:g})."
        ),
        Table(header=["A", "B", "paired jobs", "SR A - B", "95% interval", "p", "p (Holm)", "significant"], rows=pairs),
        *(Paragraph(text=f"Warning: {w}") for w in ranking.warnings),
    ]
