"""Two systems compared on the jobs both ran: SR and PSR differences with honest uncertainty.

A system is one agent/model of one run directory, optionally in one mode
(``RUN_DIR[:SYSTEM][@MODE]``). Jobs are paired by task, seed and drag setting, and by mode
unless a side names one (then composite and primitive of one model can be compared: the
reasoning-acting gap). Only pairs where both sides have a verdict count. The uncertainty is
resampled over tasks, not jobs, because the seeds of one task are not independent of each other.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Literal, get_args

from pydantic import BaseModel

from scratchworld_dist._errors import NotARunDirError, RunDirError
from scratchworld_dist.kinds.tasks.report._stable_only import (
    StableOnly,
    left_out_tests,
    stable_only_note,
    stable_verdicts,
)
from scratchworld_dist.kinds.tasks.report._summary import DETERMINATE
from scratchworld_dist.kinds.tasks.report._verdict_changes import VerdictChange, verdict_changes
from scratchworld_dist.reports import (
    Interval,
    LaterFields,
    LoadedRun,
    McNemar,
    incompatibilities,
    load_run,
    mcnemar_exact,
    paired_bootstrap,
    row_label,
)
from scratchworld_dist.results import JobRow, RunManifest, effective_rows
from workers.contract import Mode

MODE_NAMES: tuple[str, ...] = get_args(Mode)

_Key = tuple[str, ...]


@dataclass(frozen=True)
class Selector:
    """What one side of a comparison names: a run directory, and maybe a system and a mode in it."""

    path: Path
    system: str | None = None
    mode: str | None = None


def parse_selector(text: str) -> Selector:
    """``RUN_DIR``, ``RUN_DIR:SYSTEM``, ``RUN_DIR@MODE`` or ``RUN_DIR:SYSTEM@MODE``.

    The run directory is the longest prefix that is an existing directory, so a path may itself
    hold ``:`` or ``@``; a system is an agent, a model label or ``agent/model`` as the report
    names its rows.
    """
    head, mode = text, None
    stem, at, tail = text.rpartition("@")
    if at and tail in MODE_NAMES and not Path(text).is_dir():
        head, mode = stem, tail
    if Path(head).is_dir():
        return Selector(Path(head), None, mode)
    cuts = [i for i, char in enumerate(head) if char == ":" and Path(head[:i]).is_dir()]
    if not cuts:
        raise NotARunDirError(text, "no such folder", "; expected RUN_DIR[:SYSTEM][@MODE]")
    cut = cuts[-1]
    system = head[cut + 1 :]
    if not system:
        raise RunDirError(f"{text}: empty system name after ':' (expected RUN_DIR[:SYSTEM][@MODE])")
    return Selector(Path(head[:cut]), system, mode)


class SideInfo(BaseModel):
    """One compared system, as resolved from its selector."""

    run_dir: str
    run_name: str
    label: str
    agent: str
    model: str
    mode: str | None
    """The mode named in the selector; ``None`` when jobs are paired by mode."""

    jobs: int
    """Jobs of this system with a result (errors included), before pairing."""


class Difference(BaseModel):
    """One rate of both systems over the paired jobs, and A - B with its interval."""

    a: float
    b: float
    difference: float
    interval: Interval | None
    """Paired bootstrap interval of ``difference``; ``None`` with fewer than two tasks."""


class TaskOutcome(BaseModel):
    """One task (and mode, when paired by mode): passes of each side over its paired jobs."""

    task_id: str
    mode: str | None
    category: str
    jobs: int
    a_passed: int
    b_passed: int
    result: Literal["win", "loss", "tie"]
    """From A's side: ``win`` when A passed more of the task's jobs than B."""


class RegradeNote(BaseModel):
    """One side regrades the other: under which conditions, and which verdicts that changed."""

    regrading: Literal["a", "b"]
    """The side that is the regrade (the other is its source)."""

    conditions: str
    changed: list[VerdictChange]
    """Regraded jobs of the compared system whose verdict differs from their source's (before: the source's)."""

    unchanged: int


class Comparison(LaterFields):
    """``scratchworld compare``'s result; its JSON form is this model's dump."""

    later_fields = ("stable_only",)

    a: SideInfo
    b: SideInfo
    paired_by: list[str]
    paired_jobs: int
    tasks: int
    only_a: int
    """Jobs A has and B does not (left out)."""

    only_b: int
    without_verdict: int
    """Pairs left out because either side ended in error."""

    sr: Difference | None
    """``None`` when no pair has a verdict on both sides."""

    psr: Difference | None
    mcnemar: McNemar
    per_task: list[TaskOutcome]
    warnings: list[str]
    regrade: RegradeNote | None = None
    """Set when one side is a regrade of the other (its conditions are then not refused)."""

    stable_only: StableOnly | None = None
    """Set with ``--stable-only``: the unstable tests left out and the verdicts that changed (left out of the
    JSON without it)."""


def compare_runs(
    a: Selector,
    b: Selector,
    *,
    force: bool = False,
    resamples: int = 10_000,
    seed: int = 0,
    stable_only: bool = False,
) -> Comparison:
    """Compare the systems ``a`` and ``b`` name (``RunDirError`` for a bad selector or incomparable runs);
    ``stable_only``: without the tests either run marks unstable."""
    run_a, run_b = load_run(a.path), load_run(b.path)
    left_out = left_out_tests([run_a, run_b]) if stable_only else None
    return compare_loaded(run_a, a, run_b, b, force=force, resamples=resamples, seed=seed, left_out=left_out)


def compare_loaded(
    run_a: LoadedRun,
    a: Selector,
    run_b: LoadedRun,
    b: Selector,
    *,
    force: bool,
    resamples: int,
    seed: int,
    left_out: dict[str, list[str]] | None,
) -> Comparison:
    """``compare_runs`` on runs already loaded; ``left_out``: the tests to judge jobs without (a ranking leaves
    out those of all its runs), None to count the verdicts as recorded."""
    rows_a, info_a = _system(run_a, a)
    rows_b, info_b = _system(run_b, b)
    stable = None
    if left_out is not None:
        rows_a, side_a = stable_verdicts(run_a, rows_a, left_out, "A")
        rows_b, side_b = stable_verdicts(run_b, rows_b, left_out, "B")
        stable = stable_only_note([run_a, run_b], left_out, [side_a, side_b])
    by_mode = a.mode is None and b.mode is None
    if not by_mode:
        for rows, info in ((rows_a, info_a), (rows_b, info_b)):
            modes = sorted({r.mode for r in rows})
            if len(modes) > 1:
                raise RunDirError(
                    f"{info.label} in {info.run_dir} ran {', '.join(modes)}: with a mode named on one side, "
                    f"name the other's too (RUN_DIR:SYSTEM@MODE)"
                )
    regrade = _regrade_note(run_a, run_b, rows_a, rows_b)
    warnings = _condition_problems(run_a, run_b, rows_a, rows_b, force=force, regrade=regrade is not None)
    keyed_a, dup_a = _keyed(rows_a, by_mode)
    keyed_b, dup_b = _keyed(rows_b, by_mode)
    if dup_a or dup_b:
        again = dup_a + dup_b
        warnings.append(f"{again} job(s) were run again under another config (another job id); the latest counts")
    shared = sorted(keyed_a.keys() & keyed_b.keys())
    pairs = [(keyed_a[k], keyed_b[k]) for k in shared]
    decided = [(x, y) for x, y in pairs if x.outcome in DETERMINATE and y.outcome in DETERMINATE]
    tasks = len({x.task_id for x, _ in decided})
    if len(decided) > tasks:
        warnings.append(
            "tasks have several paired jobs (seeds, modes, settings): McNemar's test treats every job as "
            "independent, which overstates the evidence; the bootstrap interval resamples whole tasks and does not"
        )
    return Comparison(
        a=info_a,
        b=info_b,
        paired_by=["task", "seed", *(["mode"] if by_mode else []), "setting"],
        paired_jobs=len(decided),
        tasks=tasks,
        only_a=len(keyed_a.keys() - keyed_b.keys()),
        only_b=len(keyed_b.keys() - keyed_a.keys()),
        without_verdict=len(pairs) - len(decided),
        sr=_difference(decided, _passed, resamples, seed),
        psr=_difference(decided, _psr, resamples, seed),
        mcnemar=mcnemar_exact([(_passed(x), _passed(y)) for x, y in decided]),
        per_task=_per_task(decided, by_mode),
        warnings=warnings,
        regrade=regrade,
        stable_only=stable,
    )


def _regrade_note(run_a: LoadedRun, run_b: LoadedRun, rows_a: list[JobRow], rows_b: list[JobRow]) -> RegradeNote | None:
    """How one side regrades the other, per its manifest (None when neither does)."""
    if _regrades(run_b, run_a):
        regrading: Literal["a", "b"] = "b"
        source, regraded, regrade_run = rows_a, rows_b, run_b
    elif _regrades(run_a, run_b):
        regrading, source, regraded, regrade_run = "a", rows_b, rows_a, run_a
    else:
        return None
    info = regrade_run.manifest.regrade
    if info is None:  # _regrades found it; this tells the type checker
        return None
    harness = regrade_run.manifest.harness.digest if regrade_run.manifest.harness else "-"
    conditions = (
        f"suite {info.suite.name} at {info.suite.root} (hash {info.suite.hash}), profile {info.profile}, "
        f"clock {info.clock}, harness {harness} (source's {info.source_harness or '-'})"
    )
    changed, unchanged = verdict_changes(source, regraded)
    return RegradeNote(regrading=regrading, conditions=conditions, changed=changed, unchanged=unchanged)


def _regrades(regrade: LoadedRun, source: LoadedRun) -> bool:
    """Whether ``regrade``'s manifest names ``source`` as what it regraded (by path, or by run and config)."""
    info = regrade.manifest.regrade
    if info is None:
        return False
    if Path(info.source_run).resolve() == source.path.resolve():
        return True
    return _same_sweep(info.source_run_name, info.source_config_hash, source.manifest)


def _same_sweep(run_name: str, config_hash: str, manifest: RunManifest) -> bool:
    """A source moved elsewhere is still known by its run name and config hash."""
    return manifest.regrade is None and (manifest.run_name, manifest.config_hash) == (run_name, config_hash)


def _system(run: LoadedRun, selector: Selector) -> tuple[list[JobRow], SideInfo]:
    """The effective rows of the one system ``selector`` names in ``run``."""
    rows = list(effective_rows(run.rows))
    systems = sorted({(r.agent, r.model) for r in rows})
    labels = ", ".join(row_label(*s) for s in systems)
    if not systems:
        raise RunDirError(f"{run.path}: no results of its manifest's suite and harness ({run.stale_rows} older rows)")
    if selector.system is None:
        if len(systems) > 1:
            raise RunDirError(f"{run.path} holds {len(systems)} systems ({labels}); name one as RUN_DIR:SYSTEM")
        chosen = systems
    else:
        chosen = [s for s in systems if selector.system in (row_label(*s), s[0], s[1])]
        if not chosen:
            raise RunDirError(f"{run.path} has no system {selector.system!r} (it has: {labels})")
        if len(chosen) > 1:
            named = ", ".join(row_label(*s) for s in chosen)
            raise RunDirError(f"{selector.system!r} names {len(chosen)} systems in {run.path} ({named}); pick one")
    agent, model = chosen[0]
    picked = [r for r in rows if (r.agent, r.model) == (agent, model)]
    if selector.mode is not None:
        picked = [r for r in picked if r.mode == selector.mode]
        if not picked:
            raise RunDirError(f"{row_label(agent, model)} in {run.path} has no {selector.mode} jobs")
    info = SideInfo(
        run_dir=str(run.path),
        run_name=run.manifest.run_name,
        label=row_label(agent, model),
        agent=agent,
        model=model,
        mode=selector.mode,
        jobs=len(picked),
    )
    return picked, info


def _condition_problems(
    run_a: LoadedRun, run_b: LoadedRun, rows_a: list[JobRow], rows_b: list[JobRow], *, force: bool, regrade: bool
) -> list[str]:
    """Warnings on the two sides' conditions; raises for what makes their verdicts incomparable, unless ``force``.

    A regrade differs from its source in suite, task contents, profile, clock or harness on purpose:
    those are its stated conditions, not problems.
    """
    if regrade:
        budget = _differs("max_steps", rows_a, rows_b)
        return [f"{budget}: the systems had different step budgets"] if budget else []
    problems = incompatibilities([run_a, run_b]) if run_a.path.resolve() != run_b.path.resolve() else []
    for field in ("eval_profile", "eval_clock", "eval_render", "eval_page", "eval_timing"):
        if differs := _differs(field, rows_a, rows_b):
            problems.append(differs)
    hashes_b = {r.task_id: r.task_hash for r in rows_b}
    changed = sorted({r.task_id for r in rows_a if hashes_b.get(r.task_id, r.task_hash) != r.task_hash})
    if changed:
        problems.append(f"{len(changed)} task(s) differ in content ({', '.join(changed[:5])})")
    if problems and not force:
        raise RunDirError(f"refusing to compare: {'; '.join(problems)}; use --force to compare anyway")
    warnings = [f"compared anyway (--force): {p}" for p in problems]
    if budget := _differs("max_steps", rows_a, rows_b):  # a choice of the systems compared, as modes are
        warnings.append(f"{budget}: the systems had different step budgets")
    return warnings


def _differs(field: str, rows_a: list[JobRow], rows_b: list[JobRow]) -> str | None:
    """``field differs (a values / b values)`` when the decided jobs of the two sides disagree on it."""
    seen_a = {str(getattr(r, field)) for r in rows_a if r.outcome in DETERMINATE}
    seen_b = {str(getattr(r, field)) for r in rows_b if r.outcome in DETERMINATE}
    if seen_a and seen_b and seen_a != seen_b:
        return f"{field} differs ({','.join(sorted(seen_a))} / {','.join(sorted(seen_b))})"
    return None


def _keyed(rows: list[JobRow], by_mode: bool) -> tuple[dict[_Key, JobRow], int]:
    """The system's rows by pairing key (the latest job of each), and how many earlier jobs that set aside."""
    keyed: dict[_Key, JobRow] = {}
    duplicates = 0
    for row in sorted(rows, key=lambda r: r.finished_at):
        key = (row.task_id, str(row.seed), *([row.mode] if by_mode else []), row.setting or "")
        duplicates += key in keyed
        keyed[key] = row
    return keyed, duplicates


def _passed(row: JobRow) -> float:
    return 1.0 if row.outcome == "passed" else 0.0


def _psr(row: JobRow) -> float:
    return row.psr if row.psr is not None else 0.0


def _difference(
    pairs: Sequence[tuple[JobRow, JobRow]], value: Callable[[JobRow], float], resamples: int, seed: int
) -> Difference | None:
    if not pairs:
        return None
    clusters: dict[str, list[tuple[float, float]]] = defaultdict(list)
    for x, y in pairs:
        clusters[x.task_id].append((value(x), value(y)))
    a = sum(value(x) for x, _ in pairs) / len(pairs)
    b = sum(value(y) for _, y in pairs) / len(pairs)
    interval = paired_bootstrap(list(clusters.values()), resamples=resamples, seed=seed) if len(clusters) > 1 else None
    return Difference(a=a, b=b, difference=a - b, interval=interval)


def _per_task(pairs: Sequence[tuple[JobRow, JobRow]], by_mode: bool) -> list[TaskOutcome]:
    groups: dict[tuple[str, str | None], list[tuple[JobRow, JobRow]]] = defaultdict(list)
    for x, y in pairs:
        groups[(x.task_id, x.mode if by_mode else None)].append((x, y))
    outcomes = []
    for (task_id, mode), members in sorted(groups.items(), key=lambda item: (item[0][0], item[0][1] or "")):
        a_passed = sum(x.outcome == "passed" for x, _ in members)
        b_passed = sum(y.outcome == "passed" for _, y in members)
        result: Literal["win", "loss", "tie"] = "tie"
        if a_passed != b_passed:
            result = "win" if a_passed > b_passed else "loss"
        outcomes.append(
            TaskOutcome(
                task_id=task_id,
                mode=mode,
                category=members[0][0].category,
                jobs=len(members),
                a_passed=a_passed,
                b_passed=b_passed,
                result=result,
            )
        )
    return outcomes
