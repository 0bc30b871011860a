"""The perception benchmark's report: accuracy both ways per kind and tag, coverage, YES share, YES/NO confusion."""

from __future__ import annotations

import json
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.perception._metrics import (
    PerceptionCell,
    PerceptionRun,
    PerceptionTable,
    PerceptionTableRow,
    join_runs,
    perception_rows,
)
from scratchworld_dist.kinds.perception._table import build_perception_report, is_perception_run
from scratchworld_dist.reports import report_runs
from scratchworld_dist.results import JobRecord
from scratchworld_dist.viewer import ViewerSite
from tests.support.cli_runner import invoke
from tests.support.run_dirs import job, make_run, perception_record

PERCEPTION_CONFIG = {"benchmark": "perception", "models": [{"model": "openai/gpt"}], "seeds": [0, 1]}


def mixed_records() -> list[JobRecord]:
    """One model's answers, each read by hand below (normalized | strict):

    c1 YES "YES" right | right; c2 NO "YES" FP | FP; c3 NO "Yes." FP | unreadable; c4 NO "no" (after an error
    attempt) right | right; c5 YES "maybe" unreadable | unreadable; c1 seed 1 an error. e1 YES "Answer: NO"
    FN | unreadable; e2 NO "" unreadable | unreadable; e3 an error of an item nobody answered. f1 "10.0" for
    10 right | wrong; f2 "Left Arrow" for the option "left arrow" right | wrong; f3 YES "YES" right | right.
    """
    return [
        perception_record("c1", "YES", "YES"),
        perception_record("c1", "YES", None, seed=1),
        perception_record("c2", "NO", "YES"),
        perception_record("c3", "NO", "Yes."),
        perception_record("c4", "NO", None),
        perception_record("c4", "NO", "no", attempt=2),
        perception_record("c5", "YES", "maybe"),
        perception_record("e1", "YES", "Answer: NO", kind="existence"),
        perception_record("e2", "NO", "", kind="existence"),
        perception_record("e3", "YES", None, kind="existence", error_class="model_unavailable"),
        perception_record("f1", "10", "10.0", kind="field", value_kind="number"),
        perception_record("f2", "left arrow", "Left Arrow", kind="field", value_kind="dropdown"),
        perception_record("f3", "YES", "YES", kind="field"),
    ]


def joined(records: list[JobRecord]) -> tuple[list[PerceptionRun], list[str]]:
    return join_runs([r.job for r in records], [a for r in records for a in r.kind_rows.get("perception", [])])


def one_row() -> PerceptionTableRow:
    runs, warnings = joined(mixed_records())
    assert warnings == []
    (row,) = perception_rows(runs)
    return row


def counts(cell: PerceptionCell) -> tuple[int, int, int, int, int]:
    return (cell.runs, cell.scored, cell.error_runs, cell.normalized.correct, cell.strict.correct)


def test_error_runs_count_in_coverage_but_never_in_an_accuracy() -> None:
    overall = one_row().overall
    assert counts(overall) == (12, 10, 2, 5, 3)
    assert (overall.coverage, overall.normalized.rate, overall.strict.rate) == (pytest.approx(10 / 12), 0.5, 0.3)
    assert (overall.normalized.scored, overall.strict.scored) == (10, 10)


def test_both_scorings_per_kind() -> None:
    row = one_row()
    kinds = {cell.group: cell for cell in row.kinds}
    assert list(kinds) == ["connection", "existence", "field"]
    assert counts(kinds["connection"]) == (6, 5, 1, 2, 2)
    assert counts(kinds["existence"]) == (3, 2, 1, 0, 0)
    assert counts(kinds["field"]) == (3, 3, 0, 3, 1)
    assert kinds["field"].strict.rate == pytest.approx(1 / 3)


def test_per_tag_in_kind_order_and_an_unanswered_items_error_under_unknown_tag() -> None:
    tags = {cell.group: cell for cell in one_row().tags}
    assert list(tags) == [
        "connection_no",
        "connection_yes",
        "(unknown tag)",
        "existence_no",
        "existence_yes",
        "field_dropdown",
        "field_number",
        "field_yes",
    ]
    # c1's error run at seed 1 takes the tag of c1's answer at seed 0.
    assert counts(tags["connection_yes"]) == (3, 2, 1, 1, 1)
    assert counts(tags["connection_no"]) == (3, 3, 0, 1, 1)
    assert (tags["(unknown tag)"].kind, counts(tags["(unknown tag)"])) == ("existence", (1, 0, 1, 0, 0))
    assert tags["(unknown tag)"].coverage == 0.0 and tags["(unknown tag)"].normalized.rate is None
    assert (tags["field_number"].normalized.rate, tags["field_number"].strict.rate) == (1.0, 0.0)


def test_yes_share_is_what_answering_yes_to_everything_scores() -> None:
    row = one_row()
    assert (row.overall.yes_expected, row.overall.yes_share) == (4, 0.4)  # c1, c5, e1, f3 of 10 scored
    assert [c.yes_share for c in row.kinds] == [pytest.approx(2 / 5), 0.5, pytest.approx(1 / 3)]
    answered = [r.kind_rows["perception"][0] for r in mixed_records() if r.kind_rows.get("perception")]
    always_yes = [
        perception_record(
            a.item_id, a.expected, "YES", kind=a.kind, value_kind=a.value_kind, model="-", agent="always_yes"
        )
        for a in answered
    ]
    runs, _ = joined(always_yes)
    (scripted,) = perception_rows(runs)
    assert scripted.overall.normalized.rate == scripted.overall.yes_share == pytest.approx(4 / 10)


def confusion_counts(cell: object) -> tuple[int, ...]:
    return tuple(
        getattr(cell, name)
        for name in (
            "true_positives",
            "false_positives",
            "true_negatives",
            "false_negatives",
            "unreadable_yes",
            "unreadable_no",
        )
    )


def test_confusion_per_kind_both_scorings_with_unreadable_answers_apart() -> None:
    confusion = {cell.group: cell for cell in one_row().confusion}
    assert list(confusion) == ["connection", "existence", "field", "ALL"]
    connection = confusion["connection"]
    assert connection.items == 5
    assert confusion_counts(connection.normalized) == (1, 2, 1, 0, 1, 0)  # "Yes." reads as YES: a false positive
    assert confusion_counts(connection.strict) == (1, 1, 1, 0, 1, 1)  # ... and strict cannot read it
    assert connection.normalized.false_positive_rate == pytest.approx(2 / 3)
    assert connection.strict.false_positive_rate == pytest.approx(1 / 3)  # unreadable NO items stay in the base
    assert confusion_counts(confusion["existence"].normalized) == (0, 0, 0, 1, 0, 1)
    assert confusion_counts(confusion["existence"].strict) == (0, 0, 0, 0, 1, 1)
    assert confusion["field"].items == 1 and confusion["field"].normalized.false_positive_rate is None
    everything = confusion["ALL"]
    assert everything.items == 8  # the yes/no items scored: errors and value items are not in it
    assert confusion_counts(everything.normalized) == (2, 2, 1, 1, 1, 1)
    assert confusion_counts(everything.strict) == (2, 1, 1, 0, 2, 2)
    assert (everything.normalized.false_positive_rate, everything.strict.false_positive_rate) == (0.5, 0.25)


def test_parse_failures_errors_and_spend() -> None:
    row = one_row()
    assert [(p.name, p.runs) for p in row.parse_failures] == [("no_answer", 1), ("unparsed", 1)]
    assert [(e.name, e.runs) for e in row.errors] == [("model_rate_limited", 1), ("model_unavailable", 1)]
    assert (row.input_tokens, row.cost_usd) == (12 * 50, pytest.approx(12 * 0.001))  # one effective row per job


def test_join_takes_the_effective_attempt_and_names_rows_that_do_not_fit() -> None:
    retried = perception_record("c4", "NO", None)
    answered = perception_record("c4", "NO", "no", attempt=2)
    orphan = perception_record("c9", "YES", "YES")
    episode = job("ep", "passed", category="create")
    records = [retried, answered, JobRecord(job=orphan.job), JobRecord(job=episode)]
    runs, warnings = joined(records)
    (run,) = runs
    assert (run.job.attempt, run.error, run.correct("strict")) == (2, False, True)
    assert warnings == [
        "1 job(s) that are not perception jobs ignored",
        "1 perception job(s) with a verdict but no perception row for their attempt left out",
    ]


def test_rows_per_model_and_agent() -> None:
    records = [
        *mixed_records(),
        perception_record("c1", "YES", "YES", model="-", agent="oracle"),
        perception_record("c1", "YES", "NO", model="other"),
    ]
    runs, _ = joined(records)
    rows = perception_rows(runs)
    assert [(r.model, r.agent, r.overall.runs) for r in rows] == [
        ("-", "oracle", 1),
        ("gpt", "llm", 12),
        ("other", "llm", 1),
    ]
    other = rows[2]
    assert other.overall.normalized.rate == 0.0 and other.confusion[0].normalized.false_negatives == 1


# -- run directories and the command ------------------------------------------------------


def perception_run(run_dir: Path, records: list[JobRecord] | None = None) -> Path:
    records = mixed_records() if records is None else records
    return make_run(run_dir, records, planned=len(records), tasks=9, config=PERCEPTION_CONFIG, name="perception")


def test_report_from_a_run_directory(tmp_path: Path) -> None:
    run_dir = perception_run(tmp_path / "run")
    assert is_perception_run(run_dir)
    table = build_perception_report([run_dir])
    (row,) = table.rows
    assert counts(row.overall) == (12, 10, 2, 5, 3)
    text, warnings = report_runs([run_dir], "md")
    assert warnings == [] and text.startswith("# ScratchWorld perception report\n")
    assert "| gpt | 83.3% (10/12) | 50.0% (5/10) | 30.0% (3/10) | 40.0% (2/5) | 40.0% (2/5) |" in text
    assert "| gpt | connection | 5 | normalized | 1 | 2 | 1 | 0 | 1 | 0 | 66.7% |" in text
    assert "| gpt | connection | 5 | strict | 1 | 1 | 1 | 0 | 1 | 1 | 33.3% |" in text
    assert "| gpt | existence | (unknown tag) | 0.0% (0/1) | - | - | - |" in text
    assert "model_rate_limited 1, model_unavailable 1 | no_answer 1, unparsed 1 |" in text


def test_a_run_whose_every_call_failed_is_still_a_perception_run(tmp_path: Path) -> None:
    records = [perception_record(f"c{i}", "YES", None) for i in range(3)]
    run_dir = perception_run(tmp_path / "run", records)
    assert is_perception_run(run_dir)  # no perception rows: the manifest says so
    (row,) = build_perception_report([run_dir]).rows
    assert counts(row.overall) == (3, 0, 3, 0, 0) and row.overall.normalized.rate is None
    assert "| gpt | 0.0% (0/3) | - | - |" in report_runs([run_dir], "md")[0]


def test_an_episode_run_is_not_a_perception_run(tmp_path: Path) -> None:
    episodes = make_run(tmp_path / "episodes", [job("a")], planned=1, tasks=1)
    assert not is_perception_run(episodes) and not is_perception_run(tmp_path / "nowhere")
    with pytest.raises(RunDirError, match="no perception job results"):
        build_perception_report([episodes])


def test_cli_renders_the_perception_report_in_each_format(tmp_path: Path) -> None:
    run_dir = perception_run(tmp_path / "run")
    md = invoke("report", str(run_dir))
    assert md.returncode == 0, md.stderr
    assert md.stdout.startswith("# ScratchWorld perception report") and "## YES/NO confusion" in md.stdout
    as_json = invoke("report", str(run_dir), "--format", "json")
    table = PerceptionTable.model_validate(json.loads(as_json.stdout))
    assert table.rows[0].overall.strict.correct == 3
    out = tmp_path / "perception.html"
    page = invoke("report", str(run_dir), "--format", "html", "--out", str(out))
    assert page.returncode == 0, page.stderr
    text = out.read_text(encoding="utf-8")
    assert text.startswith("<!DOCTYPE html>") and "<h1>ScratchWorld perception report</h1>" in text
    assert "<td>(unknown tag)</td>" in text


def test_a_bad_perception_row_is_a_one_line_error(tmp_path: Path) -> None:
    run_dir = perception_run(tmp_path / "run", mixed_records()[:1])
    shard = next((run_dir / "perception").glob("*.parquet"))
    table = pq.read_table(shard)
    pq.write_table(table.set_column(table.schema.get_field_index("kind"), "kind", pa.array([None], pa.string())), shard)
    done = invoke("report", str(run_dir))
    assert done.returncode == 2 and done.stderr.startswith("error: ") and "not a perception answer" in done.stderr


def test_the_viewer_shows_a_perception_runs_report(tmp_path: Path) -> None:
    page = ViewerSite([perception_run(tmp_path / "run")]).get("runs/0/index.html")
    assert page is not None and page.body is not None
    assert b"<h2>YES/NO confusion (YES = positive)</h2>" in page.body and b"<td>(unknown tag)</td>" in page.body
