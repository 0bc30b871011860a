"""The grader audit does not trust the grader: a copy of our sum_two_numbers whose tests pass everything without
starting the program (``blind``), and one whose tests click the flag and read nothing the program does (``deaf``).
Judged by their own tests' runs alone every surviving mutant looked equivalent; the exploration shows them holes,
and the report names both graders vacuous before any score. A declaration explains the deaf task's holes: they are
listed apart and the score counts the others."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from scratchworld_dist.kinds.audit import build_audit_report, render_audit
from scratchworld_dist.results import RunStore
from tests.support.cli_runner import invoke
from tests.support.small_suites import native_suite

pytestmark = [pytest.mark.ray, pytest.mark.browser, pytest.mark.slow]

BLIND = """
module.exports = async (vm) => Harness.runTests(vm, [
  {name: 'the sum is right', timeoutMs: 1000, run: async () => ({passed: true})},
]);
"""

DEAF = """
module.exports = async (vm) => Harness.runTests(vm, [
  {name: 'the sprite is there', timeoutMs: 3000, run: async () => {
    await Harness.start(vm);
    return {passed: Harness.sprite(vm, 'Calculator').size > 0};
  }},
]);
"""

MUTANTS = 4


@pytest.fixture(scope="module")
def audited(tmp_path_factory: pytest.TempPathFactory, shared_ray: int) -> tuple[Path, Path, str]:
    root = tmp_path_factory.mktemp("vacuous")
    suite = root / "suite"
    blind = native_suite(suite, "blind")
    shutil.copytree(blind, blind.parent / "deaf")
    (blind / "evaluate.js").write_text(BLIND)
    (blind.parent / "deaf" / "evaluate.js").write_text(DEAF)
    out = root / "audit"
    done = invoke(
        "audit", str(suite), "--mutants-per-task", str(MUTANTS), "--refactorings-per-task", "0", "--out", str(out)
    )
    assert done.returncode == 0, done.stderr
    return suite, out, done.stdout


def test_every_surviving_mutant_of_a_vacuous_grader_is_a_hole_shown_by_the_exploration(
    audited: tuple[Path, Path, str],
) -> None:
    _, out, _ = audited
    rows = RunStore(out).read_table("audits").to_pylist()
    mutants = [row for row in rows if row["variant"] == "mutant"]
    assert len(mutants) == 2 * MUTANTS
    assert {row["verdict"] for row in mutants} == {"hole"}  # none killed, none equivalent
    for row in mutants:
        shown_by = json.loads(row["shown_by"])
        assert row["evidence"] and json.loads(row["first_difference"])["frame"] >= 1
        if row["task_id"] == "blind":  # its tests' run shows nothing (nothing runs): the exploration does
            assert shown_by["run"].startswith("seed ") and row["runs_compared"] >= 2
    goldens = {row["task_id"]: row for row in rows if row["variant"] == "golden"}
    assert goldens["blind"]["vacuous"] == "never_starts" and goldens["deaf"]["vacuous"] == "observes_nothing"
    deaf = json.loads(goldens["deaf"]["grader"])
    assert deaf["started"] and ["Calculator", "size"] in deaf["reads"] and ["Calculator", "bubble"] in deaf["changes"]


def test_the_report_names_vacuous_graders_before_any_score_and_scores_on_unexplained_holes(
    audited: tuple[Path, Path, str], tmp_path: Path
) -> None:
    suite, out, stdout = audited
    assert stdout.index("## Vacuous graders (2)") < stdout.index("Mutation score")
    assert "blind: never_starts: its tests never start the program" in stdout
    report = build_audit_report([out])
    assert [(v.task_id, v.vacuous) for v in report.vacuous] == [("blind", "never_starts"), ("deaf", "observes_nothing")]
    assert {t.task_id: t.vacuous for t in report.tasks} == {"blind": "never_starts", "deaf": "observes_nothing"}
    assert report.total.holes == 2 * MUTANTS and report.mutation_score == 0.0 and report.explained == []
    # The suite declares the deaf task's differences open (a report-time reading: the run stays as it is).
    declared = tmp_path / "suite"
    shutil.copytree(suite, declared)
    reason = "every difference is open (a test of this test)"
    (declared / "compute" / "deaf" / "audit.yaml").write_text(
        f"explained:\n  - reason: {reason}\n    match: {{target: Calculator}}\n"
    )
    moved = tmp_path / "run"
    shutil.copytree(out, moved)
    manifest = json.loads((moved / "manifest.json").read_text())
    manifest["config"]["suite"] = str(declared)
    (moved / "manifest.json").write_text(json.dumps(manifest))
    explained = build_audit_report([moved])
    assert {f.task_id for f in explained.explained} == {"deaf"} and len(explained.explained) == MUTANTS
    assert all(f.explanation and f.explanation.startswith(reason) for f in explained.explained)
    assert {f.task_id for f in explained.holes} == {"blind"} and explained.total.explained == MUTANTS
    assert explained.total.holes == MUTANTS and explained.mutation_score == 0.0
    (deaf,) = [t for t in explained.tasks if t.task_id == "deaf"]
    assert deaf.explained == MUTANTS and deaf.holes == 0 and deaf.mutation_score is None
    markdown = render_audit(explained, "md")
    assert f"## Explained holes ({MUTANTS})" in markdown and f"explained: {reason}" in markdown
    # An unreadable declaration is a warning of the report, never a silent "explained".
    (declared / "compute" / "deaf" / "audit.yaml").write_text("explained: [{reason: r}]\n")
    broken = build_audit_report([moved])
    assert broken.explained == [] and any("declarations cannot be read" in w for w in broken.warnings)
