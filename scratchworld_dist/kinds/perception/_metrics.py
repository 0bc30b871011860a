"""The perception benchmark's metrics as pure functions over rows: accuracy both ways, coverage, YES/NO confusion.

One *run* is the effective attempt of one perception job (item, seed, agent, model; ``effective_rows``),
joined to the ``perception`` row of the same (job_id, attempt). A run that ended in error (the model call
failed for good) has no answer: it is counted by error class and in coverage (scored / runs), and left
out of every accuracy's denominator. Upstream drops failed calls from its denominator without a word;
here they stay in view.

Both scorings are kept side by side: ``strict`` (upstream's: the stripped reply equals the answer) and
``normalized`` (ours: the final answer read out of the reply). On yes/no items the confusion takes YES as
the positive class, so a false positive on a connection item is a link seen where there is none, the
failure the paper names. A wrong answer that a scoring cannot read as the opposite of the expected one
(under strict: anything but a bare YES or NO) is not forced into a cell: it is counted as unreadable.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Iterable, Sequence
from typing import Literal

from pydantic import BaseModel, ConfigDict

from scratchworld_dist.kinds.perception._rows import PerceptionRow
from scratchworld_dist.reports import ClassCount, class_counts
from scratchworld_dist.results import JobRow, effective_rows
from workers.kinds.perception import NO, PERCEPTION_KINDS, YES

ALL = "ALL"
"""The group that pools every kind (or every tag)."""

Scoring = Literal["normalized", "strict"]
SCORINGS: tuple[Scoring, ...] = ("normalized", "strict")
"""Ours first: it decides a job's outcome."""


class PerceptionRun(BaseModel):
    """One run: the job's effective row and, unless it ended in error, its perception row."""

    model_config = ConfigDict(frozen=True)

    job: JobRow
    answer: PerceptionRow | None
    tag: str | None
    """The item's tag: from the answer, or for an error run from another run of the same item (None if none)."""

    @property
    def error(self) -> bool:
        return self.answer is None

    @property
    def kind(self) -> str:
        return self.answer.kind if self.answer is not None else self.job.category

    def correct(self, scoring: Scoring) -> bool:
        """Whether the answer is right under ``scoring`` (False for an error run, which is never scored)."""
        if self.answer is None:
            return False
        return self.answer.normalized_correct if scoring == "normalized" else self.answer.strict_correct

    def reading(self, scoring: Scoring) -> str | None:
        """The YES or NO that ``scoring`` read in the answer; None when it read neither (or there is no answer)."""
        if self.answer is None:
            return None
        read = self.answer.extracted if scoring == "normalized" else self.answer.reply.strip()
        read = (read or "").upper()
        return read if read in (YES, NO) else None


class Accuracy(BaseModel):
    """Right answers among the scored runs of a group, under one scoring."""

    correct: int
    scored: int
    rate: float | None
    """``correct / scored``; None without scored runs."""


class PerceptionCell(BaseModel):
    """One (model, agent) over one group of items: a kind, a tag, or ``ALL``."""

    group: str
    kind: str | None
    """The kind of a kind's or a tag's items (None for ``ALL``, and for a tag whose items span kinds)."""

    runs: int
    """Every run of the group, error runs included."""

    scored: int
    """Runs with an answer: the accuracies' denominator."""

    error_runs: int
    coverage: float | None
    """``scored / runs``."""

    normalized: Accuracy
    strict: Accuracy
    yes_expected: int
    """Scored runs whose expected answer is YES."""

    yes_share: float | None
    """``yes_expected / scored``: the accuracy of answering YES to everything (what ``always_yes`` scores)."""


class Confusion(BaseModel):
    """YES/NO answers to yes/no items against the expected answer under one scoring; YES is the positive class."""

    true_positives: int
    false_positives: int
    """NO items answered YES."""

    true_negatives: int
    false_negatives: int
    """YES items answered NO."""

    unreadable_yes: int
    """YES items whose wrong answer the scoring read as neither YES nor NO."""

    unreadable_no: int
    """NO items whose wrong answer the scoring read as neither YES nor NO."""

    false_positive_rate: float | None
    """``false_positives / NO items scored`` (unreadable ones included in the denominator); None without NO items."""


class ConfusionCell(BaseModel):
    """The confusion of one (model, agent) over the yes/no items of one kind or of ``ALL``, both scorings."""

    group: str
    items: int
    """Scored runs of yes/no items."""

    normalized: Confusion
    strict: Confusion


class PerceptionTableRow(BaseModel):
    """One (model, agent): its accuracy overall, per kind and per tag, its confusion, errors and parse failures."""

    model: str
    agent: str
    overall: PerceptionCell
    kinds: list[PerceptionCell]
    """connection, existence and field always (a kind without runs has zero runs), then any others seen."""

    tags: list[PerceptionCell]
    """In kind order, then by tag."""

    confusion: list[ConfusionCell]
    """Per kind with yes/no items, then ``ALL``."""

    errors: list[ClassCount]
    """Error runs by error class, most frequent first."""

    parse_failures: list[ClassCount]
    """Scored runs whose reply the normalized reading found no answer in (``no_answer``, ``unparsed``)."""

    input_tokens: int
    output_tokens: int
    cost_usd: float
    """Spend of the runs (error runs included, superseded attempts not)."""


class PerceptionTable(BaseModel):
    """The perception report: its runs, warnings, and one row per (model, agent)."""

    version: int = 1
    runs: list[str]
    """The run directories read, as ``name (path)``."""

    warnings: list[str]
    rows: list[PerceptionTableRow]


def join_runs(jobs: Iterable[JobRow], answers: Iterable[PerceptionRow]) -> tuple[list[PerceptionRun], list[str]]:
    """Effective perception runs, and warnings for rows that do not fit (other jobs, verdicts without an answer)."""
    by_attempt = {(a.job_id, a.attempt): a for a in answers}
    tags = {a.item_id: a.tag for a in by_attempt.values()}
    runs: list[PerceptionRun] = []
    others = orphans = mismatched = 0
    for job in effective_rows(list(jobs)):
        answer = by_attempt.get((job.job_id, job.attempt))
        if job.outcome == "error" and job.setting is None and job.category in PERCEPTION_KINDS:
            runs.append(PerceptionRun(job=job, answer=None, tag=tags.get(job.task_id)))
        elif answer is not None:
            mismatched += answer.normalized_correct != (job.outcome == "passed")
            runs.append(PerceptionRun(job=job, answer=answer, tag=answer.tag))
        elif job.outcome == "error" or job.setting is not None or job.category not in PERCEPTION_KINDS:
            others += 1
        else:
            orphans += 1
    notes = [
        (others, "job(s) that are not perception jobs ignored"),
        (orphans, "perception job(s) with a verdict but no perception row for their attempt left out"),
        (mismatched, "perception row(s) whose normalized verdict disagrees with the job's outcome (the row counts)"),
    ]
    return runs, [f"{n} {text}" for n, text in notes if n]


def perception_rows(runs: Sequence[PerceptionRun]) -> list[PerceptionTableRow]:
    """The report's rows: one per (model, agent), sorted by model then agent."""
    groups: dict[tuple[str, str], list[PerceptionRun]] = defaultdict(list)
    for run in runs:
        groups[(run.job.model, run.job.agent)].append(run)
    return [perception_row(model, agent, members) for (model, agent), members in sorted(groups.items())]


def perception_row(model: str, agent: str, runs: Sequence[PerceptionRun]) -> PerceptionTableRow:
    """One (model, agent) from its runs (error runs included; they are counted, not scored)."""
    kinds = list(PERCEPTION_KINDS) + sorted({r.kind for r in runs} - set(PERCEPTION_KINDS))
    order = {kind: i for i, kind in enumerate(kinds)}
    by_tag: dict[str, list[PerceptionRun]] = defaultdict(list)
    for run in runs:
        by_tag[run.tag or "(unknown tag)"].append(run)

    def tag_order(tag: str) -> tuple[int, str]:
        members = {r.kind for r in by_tag[tag]}
        return (min(order[k] for k in members), tag)

    tags = sorted(by_tag, key=tag_order)
    confused = [kind for kind in kinds if any(_yes_no(r) for r in runs if r.kind == kind)]
    scored = [r for r in runs if r.answer is not None]
    return PerceptionTableRow(
        model=model,
        agent=agent,
        overall=perception_cell(ALL, None, runs),
        kinds=[perception_cell(kind, kind, [r for r in runs if r.kind == kind]) for kind in kinds],
        tags=[perception_cell(tag, _only({r.kind for r in by_tag[tag]}), by_tag[tag]) for tag in tags],
        confusion=[confusion_cell(k, [r for r in runs if r.kind == k]) for k in confused] + [confusion_cell(ALL, runs)],
        errors=class_counts(r.job.error_class or "unknown" for r in runs if r.error),
        parse_failures=class_counts(r.answer.parse for r in scored if r.answer is not None and r.answer.parse != "ok"),
        input_tokens=sum(r.job.input_tokens for r in runs),
        output_tokens=sum(r.job.output_tokens for r in runs),
        cost_usd=sum(r.job.cost_usd for r in runs),
    )


def perception_cell(group: str, kind: str | None, runs: Sequence[PerceptionRun]) -> PerceptionCell:
    """Coverage, both accuracies and the YES share of one group's runs."""
    scored = [r for r in runs if r.answer is not None]
    yes = sum(r.answer is not None and r.answer.expected.strip().upper() == YES for r in scored)
    return PerceptionCell(
        group=group,
        kind=kind,
        runs=len(runs),
        scored=len(scored),
        error_runs=len(runs) - len(scored),
        coverage=_ratio(len(scored), len(runs)),
        normalized=accuracy(scored, "normalized"),
        strict=accuracy(scored, "strict"),
        yes_expected=yes,
        yes_share=_ratio(yes, len(scored)),
    )


def accuracy(scored: Sequence[PerceptionRun], scoring: Scoring) -> Accuracy:
    """Right answers under ``scoring`` among runs that all have an answer."""
    correct = sum(r.correct(scoring) for r in scored)
    return Accuracy(correct=correct, scored=len(scored), rate=_ratio(correct, len(scored)))


def confusion_cell(group: str, runs: Sequence[PerceptionRun]) -> ConfusionCell:
    """Both confusions over the scored yes/no runs among ``runs``."""
    items = [r for r in runs if _yes_no(r)]
    return ConfusionCell(
        group=group,
        items=len(items),
        normalized=confusion(items, "normalized"),
        strict=confusion(items, "strict"),
    )


def confusion(runs: Sequence[PerceptionRun], scoring: Scoring) -> Confusion:
    """The confusion of scored yes/no runs under ``scoring``.

    Whether an answer is right is the scoring's own verdict (so TP + TN is its correct count); a wrong one
    is a false positive or negative only when the scoring read the opposite answer, else unreadable.
    """
    cells: Counter[tuple[str, str]] = Counter()
    for run in runs:
        assert run.answer is not None  # callers pass scored runs only
        expected = run.answer.expected.strip().upper()
        if run.correct(scoring):
            cells[(expected, "right")] += 1
        elif run.reading(scoring) not in (None, expected):
            cells[(expected, "opposite")] += 1
        else:
            cells[(expected, "unreadable")] += 1
    negatives = sum(n for (expected, _), n in cells.items() if expected == NO)
    return Confusion(
        true_positives=cells[(YES, "right")],
        false_positives=cells[(NO, "opposite")],
        true_negatives=cells[(NO, "right")],
        false_negatives=cells[(YES, "opposite")],
        unreadable_yes=cells[(YES, "unreadable")],
        unreadable_no=cells[(NO, "unreadable")],
        false_positive_rate=_ratio(cells[(NO, "opposite")], negatives),
    )


def _yes_no(run: PerceptionRun) -> bool:
    """A scored run of a yes/no item (error runs have no answer to confuse)."""
    return run.answer is not None and run.answer.answer_format == "yes_no"


def _only(values: set[str]) -> str | None:
    return next(iter(values)) if len(values) == 1 else None


def _ratio(part: int, whole: int) -> float | None:
    return part / whole if whole else None
