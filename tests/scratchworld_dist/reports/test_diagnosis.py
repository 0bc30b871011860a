"""The diagnosis table over runs of three benchmarks: models matched by identity, missing values as dashes."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from pydantic import BaseModel

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.kinds.tasks._diagnosis import sr_gap
from scratchworld_dist.reports import MISSING, diagnosis_models, report_runs
from scratchworld_dist.reports._diagnosis import models_of
from scratchworld_dist.reports._model_identity import ModelResolver
from scratchworld_dist.reports._run_groups import run_benchmark
from scratchworld_dist.results import RunManifest
from scratchworld_dist.sweep import SuiteInfo
from tests.support.cli_runner import invoke
from tests.support.run_dirs import drag_record, job, make_run, perception_record

GPT_T0 = {"model": "openai/gpt-4o", "name": "gpt-4o", "temperature": 0}
CLAUDE = {"model": "openai/claude", "name": "claude"}


def episode_run(run_dir: Path) -> Path:
    """gpt-4o in both modes over seeds 0 and 1, claude in both modes at seed 0 only.

    gpt-4o composite: seed 0 2/3, seed 1 3/3; primitive: seed 0 1/3, seed 1 1/2 (and an error, left out).
    claude composite 1/3, primitive 0/3.
    """
    outcomes = {
        ("gpt-4o", "composite", 0): ["passed", "passed", "failed"],
        ("gpt-4o", "composite", 1): ["passed", "passed", "passed"],
        ("gpt-4o", "primitive", 0): ["passed", "failed", "failed"],
        ("gpt-4o", "primitive", 1): ["passed", "failed", "error"],
        ("claude", "composite", 0): ["passed", "failed", "failed"],
        ("claude", "primitive", 0): ["failed", "failed", "failed"],
    }
    rows = [
        job(f"{model}-{mode}-{seed}-{task}", outcome, model=model, mode=mode, seed=seed, task_id=f"t{task}")
        for (model, mode, seed), results in outcomes.items()
        for task, outcome in enumerate(results)
    ]
    config = {
        "agent": "llm",
        "models": [GPT_T0, CLAUDE],
        "episodes": {"modes": ["composite", "primitive"]},
        "seeds": [0, 1],
    }
    return make_run(run_dir, rows, planned=24, tasks=3, config=config, name="episodes")


def drag_run(run_dir: Path) -> Path:
    """gpt-4o at T=0 named "4o" here (baseline: a passes then fails, b misses the start then misses the end;
    gt_start: both pass), gpt-4o at T=0.7 (one baseline pass) and the oracle; claude is not in it."""
    fields: dict[str, Any] = {"suite_hash": "drag1"}
    records = [
        drag_record("a", 0, "passed", model="4o", **fields),
        drag_record("a", 1, "failed", model="4o", **fields),
        drag_record("b", 0, "failed", start=5.0, model="4o", **fields),
        drag_record("b", 1, "failed", model="4o", **fields),
        drag_record("a", 0, "passed", model="4o", setting="gt_start", **fields),
        drag_record("b", 0, "passed", model="4o", setting="gt_start", **fields),
        drag_record("a", 0, "passed", model="gpt-4o", **fields),
        drag_record("a", 0, "passed", model="-", agent="oracle", **fields),
    ]
    models = [{**GPT_T0, "name": "4o"}, {**GPT_T0, "temperature": 0.7}]
    config = {"benchmark": "drag", "models": models, "drag": {"agents": ["oracle", "llm"]}, "seeds": [0, 1]}
    return make_run(run_dir, records, planned=8, tasks=2, config=config, suite_hash="drag1", name="drag")


def perception_run(run_dir: Path, name: str = "claude-3", suite_hash: str = "perc1") -> Path:
    """gpt-4o (T=0): connection 1/2 both ways, existence 1/1 normalized and 0/1 strict, one error run;
    claude (named ``name`` here): connection 0/1, existence 1/1; the oracle: connection 1/1."""
    fields: dict[str, Any] = {"suite_hash": suite_hash}
    records = [
        perception_record("c1", "YES", "YES", model="gpt-4o", **fields),
        perception_record("c2", "NO", "Yes.", model="gpt-4o", **fields),
        perception_record("c3", "NO", None, model="gpt-4o", **fields),
        perception_record("e1", "YES", "yes, I see it", kind="existence", model="gpt-4o", **fields),
        perception_record("c1", "YES", "NO", model=name, **fields),
        perception_record("e1", "YES", "YES", kind="existence", model=name, **fields),
        perception_record("c1", "YES", "YES", model="-", agent="oracle", **fields),
    ]
    config = {"benchmark": "perception", "models": [{**GPT_T0, "temperature": 0.0}, {**CLAUDE, "name": name}]}
    return make_run(run_dir, records, planned=7, tasks=3, config=config, suite_hash=suite_hash, name="perception")


def three_runs(root: Path) -> list[Path]:
    return [episode_run(root / "episodes"), drag_run(root / "drag"), perception_run(root / "perception")]


def table_of(paths: list[Path]) -> Any:
    text, _ = report_runs(paths, "json")
    return diagnosis_models().report.model_validate_json(text).diagnosis


def by_label(table: Any) -> dict[str, Any]:
    return {row.label: row for row in table.rows}


def test_runs_are_sorted_by_benchmark(tmp_path: Path) -> None:
    assert [run_benchmark(path) for path in three_runs(tmp_path)] == ["tasks", "drag", "perception"]


def test_three_benchmarks_join_per_model_identity(tmp_path: Path) -> None:
    table = table_of(three_runs(tmp_path))
    rows = by_label(table)
    assert list(rows) == [
        "claude (also named claude-3)",
        "gpt-4o (T=0) (also named 4o)",
        "gpt-4o (T=0.7)",
        "oracle [scripted]",
    ]
    assert (table.drag_settings, table.perception_kinds) == (["baseline", "gt_start"], ["connection", "existence"])
    gpt = rows["gpt-4o (T=0) (also named 4o)"]
    assert gpt.labels == ["gpt-4o", "4o"] and not gpt.scripted
    assert gpt.models == [{"model": "openai/gpt-4o", "temperature": 0.0, "max_tokens": None, "params": {}}]
    assert (gpt.composite_sr.value, gpt.composite_sr.n) == (pytest.approx(5 / 6), 6)
    assert (gpt.primitive_sr.value, gpt.primitive_sr.n) == (pytest.approx(2 / 5), 5)
    # Pass@1: task a 1/2, task b 0/2; start: 3 of 4 pressed inside; end: 1 connected of those 3.
    assert {s: (r.value, r.n) for s, r in gpt.drag_pass_at_1.items()} == {"baseline": (0.25, 4), "gt_start": (1.0, 2)}
    assert (gpt.drag_start_accuracy.value, gpt.drag_start_accuracy.n) == (0.75, 4)
    assert (gpt.drag_end_accuracy.value, gpt.drag_end_accuracy.n) == (pytest.approx(1 / 3), 3)
    perception = {k: (r.normalized, r.strict, r.n) for k, r in gpt.perception.items()}
    assert perception == {
        "connection": (0.5, 0.5, 2),
        "existence": (1.0, 0.0, 1),
        "ALL": (pytest.approx(2 / 3), pytest.approx(1 / 3), 3),  # the error run is in no denominator
    }


def test_a_model_missing_from_a_run_has_no_value_there_never_zero(tmp_path: Path) -> None:
    paths = three_runs(tmp_path)
    rows = by_label(table_of(paths))
    claude = rows["claude (also named claude-3)"]
    assert claude.drag_pass_at_1 == {} and claude.drag_start_accuracy is None and claude.drag_end_accuracy is None
    assert claude.perception["connection"].normalized == 0.0  # a measured 0 stays 0
    hot = rows["gpt-4o (T=0.7)"]
    assert (hot.composite_sr, hot.gap, hot.perception) == (None, None, {})
    oracle = rows["oracle [scripted]"]
    assert oracle.scripted and oracle.models == [] and oracle.drag_pass_at_1["baseline"].value == 1.0
    text, _ = report_runs(paths, "md")
    lines = {line.split(" | ")[0]: line for line in text.splitlines() if line.startswith("| ")}
    dash = MISSING  # an en dash, not a hyphen
    assert lines["| claude (also named claude-3)"] == (
        f"| claude (also named claude-3) | 33.3% (n=3) | 0.0% (n=3) | +33.3 (1 seed, no CI) | {dash} | {dash} | {dash} "
        f"| {dash} | 0.0% / 0.0% (n=1) | 100.0% / 100.0% (n=1) | 50.0% / 50.0% (n=2) |"
    )
    assert lines["| gpt-4o (T=0.7)"] == (
        f"| gpt-4o (T=0.7) | {dash} | {dash} | {dash} | 100.0% (n=1) | {dash} | 100.0% (n=1) | 100.0% (n=1) "
        f"| {dash} | {dash} | {dash} |"
    )


def test_the_gap_has_an_interval_over_two_seeds_and_none_over_one(tmp_path: Path) -> None:
    rows = by_label(table_of(three_runs(tmp_path)))
    gap = rows["gpt-4o (T=0) (also named 4o)"].gap
    assert gap is not None and gap.seeds == 2
    # per-seed gaps 2/3 - 1/3 and 1 - 1/2: mean 5/12; t(1) = 12.7062 times their standard error |1/3 - 1/2| / 2.
    assert gap.points == pytest.approx(100 * 5 / 12)
    assert gap.half_width == pytest.approx(100 * 12.7062047 / 12)
    single = rows["claude (also named claude-3)"].gap
    assert single is not None and (single.points, single.half_width, single.seeds) == (pytest.approx(100 / 3), None, 1)
    text, _ = report_runs(three_runs(tmp_path / "again"), "md")
    assert "| +41.7 ± 105.9 (2 seeds) |" in text


def test_gap_needs_both_modes_and_pairs_seeds() -> None:
    composite = [job(f"c{s}", "passed", seed=s) for s in (0, 1)]
    primitive = [job("p0", "failed", mode="primitive", seed=0), job("p2", "passed", mode="primitive", seed=2)]
    assert sr_gap(composite) is None
    gap = sr_gap(composite + primitive)  # seed 0 is the only seed decided in both: the pooled difference
    assert gap is not None and (gap.points, gap.half_width, gap.seeds) == (50.0, None, 1)


def resolver(config: dict[str, Any]) -> ModelResolver:
    suite = SuiteInfo(name="s", kind="native", root="/s", hash="h", tasks=1)
    manifest = RunManifest(run_name="r", schema_version=1, config=config, config_hash="c", suite=suite, planned_jobs=1)
    return ModelResolver(manifest, "r/manifest.json")


def test_identity_is_the_model_and_its_sampling_not_its_label_nor_where_it_is_served() -> None:
    first = resolver({"models": [{**GPT_T0, "api_base": "http://a", "rate_limits": {"requests_per_minute": 5}}]})
    second = resolver({"models": [{**GPT_T0, "name": "4o", "api_key_env": "KEY", "coordinates": "pixels"}]})
    hotter = resolver({"models": [{**GPT_T0, "temperature": 0.7}]})
    assert first.resolve("llm", "gpt-4o").key == second.resolve("llm", "4o").key
    assert first.resolve("llm", "gpt-4o").key != hotter.resolve("llm", "gpt-4o").key
    assert first.resolve("llm", "gpt-4o").key != first.resolve("awm", "gpt-4o").key  # another agent, another row
    assert first.resolve("oracle", "-").key.scripted


def test_a_plus_label_matches_only_the_same_combination() -> None:
    def planner_grounder(grounder: dict[str, Any]) -> ModelResolver:
        agent = {"name": "planner_grounder", "params": {"grounder": grounder}}
        return resolver({"agent": agent, "models": [GPT_T0]})

    ui_tars = {"name": "uitars", "model": "openai/ui-tars", "coordinates": "smart_resize"}
    pair = planner_grounder(ui_tars).resolve("planner_grounder", "gpt-4o+uitars")
    same = planner_grounder({**ui_tars, "api_base": "http://elsewhere"}).resolve("planner_grounder", "gpt-4o+uitars")
    other = planner_grounder({**ui_tars, "temperature": 1.0}).resolve("planner_grounder", "gpt-4o+uitars")
    alone = planner_grounder(ui_tars).resolve("planner_grounder", "gpt-4o")
    assert pair.key == same.key and pair.key != other.key and pair.key != alone.key
    assert [name for name, _ in pair.components] == ["gpt-4o", "uitars"]


def test_a_label_the_manifest_does_not_describe_is_matched_by_label_and_said(tmp_path: Path) -> None:
    unknown = resolver({"models": [GPT_T0]})
    assert unknown.resolve("llm", "mystery").components == (("mystery", {"label": "mystery"}),)
    assert unknown.unresolved == {"mystery"}
    episodes = make_run(
        tmp_path / "episodes", [job("a", model="mystery")], planned=1, tasks=1, config={"models": [GPT_T0]}
    )
    _, warnings = report_runs([episodes, perception_run(tmp_path / "perception")], "md")
    assert any("model(s) mystery not in the manifest's models: matched by label only" in w for w in warnings)


def test_a_bad_model_entry_in_a_manifest_is_a_one_line_error(tmp_path: Path) -> None:
    config = {"models": [{"model": "openai/gpt-4o", "temperature": -1}]}
    episodes = make_run(tmp_path / "episodes", [job("a", model="openai/gpt-4o")], planned=1, tasks=1, config=config)
    with pytest.raises(RunDirError, match=r"config.models\[0\] is not a model"):
        report_runs([episodes, perception_run(tmp_path / "perception")], "md")


def test_runs_merge_only_within_their_benchmark(tmp_path: Path) -> None:
    paths = three_runs(tmp_path)
    other = perception_run(tmp_path / "other-perception", suite_hash="perc2")
    with pytest.raises(RunDirError, match="runs differ in suite hash"):
        report_runs([*paths, other], "md")
    text, warnings = report_runs([*paths, other], "md", force=True)
    assert any("merged anyway (--force)" in w for w in warnings) and text.startswith("# ScratchWorld diagnosis")


def test_html_escapes_a_hostile_model_name(tmp_path: Path) -> None:
    hostile = "<img src=x onerror=alert(1)>&"
    paths = [episode_run(tmp_path / "episodes"), perception_run(tmp_path / "perception", name=hostile)]
    page, _ = report_runs(paths, "html")
    assert page.startswith("<!DOCTYPE html>") and "<img src=x" not in page
    assert "claude (also named &lt;img src=x onerror=alert(1)&gt;&amp;)" in page


def test_cli_report_of_three_benchmarks(tmp_path: Path) -> None:
    paths = [str(p) for p in three_runs(tmp_path)]
    md = invoke("report", *paths)
    assert md.returncode == 0, md.stderr
    titles = [line for line in md.stdout.splitlines() if line.startswith("# ")]
    assert titles == [
        "# ScratchWorld diagnosis",
        "# ScratchWorld report",
        "# ScratchWorld single-step drag report",
        "# ScratchWorld perception report",
    ]
    header = next(line for line in md.stdout.splitlines() if line.startswith("| agent/model | composite SR"))
    assert header == (
        "| agent/model | composite SR | primitive SR | gap (pp, 95% CI) | drag Pass@1 baseline | drag Pass@1 gt_start "
        "| drag start acc. (baseline) | drag end acc. (baseline) | perception connection (norm. / strict) "
        "| perception existence (norm. / strict) | perception overall (norm. / strict) |"
    )
    as_json = invoke("report", *paths, "--format", "json")
    report = diagnosis_models().report.model_validate(json.loads(as_json.stdout))
    assert report.episodes is not None and report.drag is not None and report.perception is not None
    assert len(report.diagnosis.rows) == 4
    out = tmp_path / "diagnosis.html"
    page = invoke("report", *paths, "--format", "html", "--out", str(out))
    assert page.returncode == 0, page.stderr
    text = out.read_text(encoding="utf-8")
    assert text.count("<!DOCTYPE html>") == 1 and "<h1>ScratchWorld diagnosis</h1>" in text
    assert "<td>oracle [scripted]</td>" in text and "<pre># ScratchWorld single-step drag report" in text


def test_two_benchmarks_show_only_their_columns(tmp_path: Path) -> None:
    text, _ = report_runs([episode_run(tmp_path / "episodes"), drag_run(tmp_path / "drag")], "md")
    header = next(line for line in text.splitlines() if line.startswith("| agent/model | composite SR"))
    assert "drag Pass@1 baseline" in header and "perception" not in header
    assert "# ScratchWorld perception report" not in text


def test_one_benchmark_keeps_its_own_report(tmp_path: Path) -> None:
    episodes = episode_run(tmp_path / "episodes")
    text, _ = report_runs([episodes, episodes], "md")
    assert text.startswith("# ScratchWorld report\n") and "diagnosis" not in text


class _Part:
    """A diagnosis part as a plugin would write one, with the three models the core builds on."""

    runs_label = definitions = ""

    def __init__(self, cells: type[BaseModel], axes: type[BaseModel] | None, section: type[BaseModel]) -> None:
        self.cells_model, self.axes_model, self.section_model = cells, axes, section


class _Cells(BaseModel):
    shared: int | None = None


class _Section(BaseModel):
    mine: int | None = None


def test_the_models_join_the_parts_fields_in_the_kinds_order_after_the_core_s() -> None:
    models = diagnosis_models()
    assert diagnosis_models() is models  # built once for the installed kinds
    row, table, report = models.row, models.table, models.report
    assert list(row.model_fields)[:5] == ["label", "agent", "scripted", "labels", "models"]
    assert list(row.model_fields)[5:] == [
        *("composite_sr", "primitive_sr", "gap", "drag_pass_at_1", "drag_start_accuracy", "drag_end_accuracy"),
        "perception",
    ]
    assert list(table.model_fields) == ["version", "runs", "drag_settings", "perception_kinds", "warnings", "rows"]
    assert list(report.model_fields) == ["version", "diagnosis", "episodes", "drag", "perception"]
    assert table.model_fields["rows"].annotation == list[row] and report.model_fields["diagnosis"].annotation is table


def test_a_part_s_fields_need_defaults_and_names_of_their_own() -> None:
    class Required(BaseModel):
        needed: int

    class Clash(BaseModel):
        label: str | None = None

    class TwoSections(BaseModel):
        first: int | None = None
        second: int | None = None

    with pytest.raises(TypeError, match=r"Required\.needed needs a default"):
        models_of((_Part(Required, None, _Section),))
    with pytest.raises(TypeError, match=r"Clash\.label is a field of the core already"):
        models_of((_Part(Clash, None, _Section),))
    with pytest.raises(TypeError, match=r"_Cells\.shared is a field of _Cells already"):
        models_of((_Part(_Cells, None, _Section), _Part(_Cells, None, _Section)))
    with pytest.raises(TypeError, match=r"section_model must have one field"):
        models_of((_Part(_Cells, None, TwoSections),))
    built = models_of((_Part(_Cells, None, _Section),))
    assert list(built.report(diagnosis=built.table(runs={}, warnings=[], rows=[])).model_dump()) == [
        *("version", "diagnosis", "mine"),
    ]
