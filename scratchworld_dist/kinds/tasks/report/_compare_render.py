"""``Comparison`` as Markdown, as an HTML page around that Markdown, or as JSON; and as the viewer shows it."""

from __future__ import annotations

from collections import Counter

import jinja2

from scratchworld_dist.kinds.tasks.report._compare import Comparison, Difference, RegradeNote, SideInfo, TaskOutcome
from scratchworld_dist.kinds.tasks.report._stable_only import stable_only_text
from scratchworld_dist.reports import ReportFormat, markdown_table, render_text

_DEFINITIONS = (
    "Only jobs both systems ran and both got a verdict for are compared (errors have no verdict). "
    "Differences are A - B. The interval is a percentile bootstrap over tasks: whole tasks are drawn with "
    "replacement (all their paired jobs together) and the pooled difference recomputed. McNemar's exact test "
    "asks whether the jobs only one system passed lean to one side more than chance would (two-sided binomial "
    "test on the discordant pairs). A task (a task in one mode, when jobs are paired by mode) is a win for A when "
    "A passed more of its paired jobs than B."
)


def render_comparison(comparison: Comparison, fmt: ReportFormat) -> str:
    """The comparison as text in ``fmt`` (``md``, ``html`` or ``json``)."""
    return render_text(comparison, lambda: render_comparison_markdown(comparison), fmt)


def render_comparison_markdown(c: Comparison) -> str:
    parts = [f"# {_side(c.a)} vs {_side(c.b)}"]
    parts += [f"Warning: {w}" for w in c.warnings]
    parts.append(f"- A: {_side(c.a)}, run {c.a.run_name} ({c.a.run_dir}), {c.a.jobs} jobs")
    parts[-1] += f"\n- B: {_side(c.b)}, run {c.b.run_name} ({c.b.run_dir}), {c.b.jobs} jobs"
    if c.stable_only is not None:
        parts.append(stable_only_text(c.stable_only))
    if c.regrade is not None:
        parts.append(_regrade_markdown(c.regrade))
    parts.append(
        f"Paired by {', '.join(c.paired_by)}: {c.paired_jobs} jobs over {c.tasks} tasks with a verdict on both "
        f"sides; left out: {c.only_a} only in A, {c.only_b} only in B, {c.without_verdict} without a verdict on "
        f"one side."
    )
    if c.sr is None or c.psr is None:
        parts.append("No paired job has a verdict on both sides: nothing to compare.")
        return "\n\n".join(parts) + "\n"
    header = ["metric", "A", "B", "A - B", "95% interval (bootstrap over tasks)"]
    parts.append(markdown_table(header, [_metric("SR", c.sr), _metric("PSR", c.psr)]))
    m = c.mcnemar
    parts.append(
        f"McNemar (exact, two-sided): only A passed {m.only_a}, only B passed {m.only_b}, both {m.both_passed}, "
        f"neither {m.neither}; p = {m.p_value:.4g}"
    )
    results = Counter(t.result for t in c.per_task)
    by_mode = "mode" in c.paired_by
    score = f"A wins {results['win']}, loses {results['loss']}, ties {results['tie']}"
    if by_mode:  # a row per task and mode: say so, rather than count the rows as tasks
        modes = len({t.mode for t in c.per_task})
        rows = f"{len(c.per_task)} rows over {c.tasks} task(s) and {modes} mode(s)"
        parts.append(f"## Per task and mode ({rows}): {score}")
    else:
        parts.append(f"## Per task ({c.tasks} task(s)): {score}")
    header = ["task", *(["mode"] if by_mode else []), "category", "A passed", "B passed", "A"]
    parts.append(markdown_table(header, [_task_cells(t, by_mode) for t in c.per_task]))
    parts.append(_DEFINITIONS)
    return "\n\n".join(parts) + "\n"


def _regrade_markdown(note: RegradeNote) -> str:
    """Which side regrades which, under what, and the jobs whose verdict it changed."""
    regrade, source = ("B", "A") if note.regrading == "b" else ("A", "B")
    lines = [
        f"{regrade} regrades {source}: {source}'s final projects evaluated again under {note.conditions}.",
        f"\n\n## Verdicts changed by the regrade: {len(note.changed)} (unchanged: {note.unchanged})",
    ]
    if note.changed:
        header = ["task", "seed", "mode", f"verdict {source} -> {regrade}", f"tests {source} -> {regrade}"]
        rows = [
            [v.task_id, str(v.seed), v.mode, f"{v.before} -> {v.after}", f"{v.tests_before} -> {v.tests_after}"]
            for v in note.changed
        ]
        lines.append("\n\n" + markdown_table(header, rows))
    return "".join(lines)


def _task_cells(t: TaskOutcome, by_mode: bool) -> list[str]:
    mode = [t.mode or ""] if by_mode else []
    return [t.task_id, *mode, t.category, f"{t.a_passed}/{t.jobs}", f"{t.b_passed}/{t.jobs}", t.result]


def _side(side: SideInfo) -> str:
    return side.label + (f"@{side.mode}" if side.mode else "")


def _metric(name: str, d: Difference) -> list[str]:
    interval = "-" if d.interval is None else f"[{_points(d.interval.low)}, {_points(d.interval.high)}]"
    return [name, f"{d.a:.1%}", f"{d.b:.1%}", _points(d.difference), interval]


def _points(value: float) -> str:
    """A difference of rates in percentage points, signed."""
    return f"{value * 100:+.1f} pp"


def comparison_html(comparison: Comparison) -> str:
    """The comparison as the viewer's comparison page shows it: an HTML fragment of its tables, escaped."""
    return _VIEWER.get_template("comparison.html").render(c=comparison)


_VIEWER = jinja2.Environment(
    loader=jinja2.PackageLoader("scratchworld_dist.kinds.tasks.report", "templates"),
    autoescape=True,
    undefined=jinja2.StrictUndefined,
    trim_blocks=True,
    lstrip_blocks=True,
)
