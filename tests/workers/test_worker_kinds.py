"""Job kinds on the worker side: the registry, each kind's harness fingerprint, and a fourth kind from a plugin.

A kind's jobs are planned and checked under the core plus that kind's own code, so an edit to drag
code changes the drag digest alone and episode runs resume; the claims are checked against the imports.
"""

from __future__ import annotations

import ast
import re
import shutil
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from scratchworld_dist._errors import RunDirError
from scratchworld_dist._run import plan_run
from scratchworld_dist._sweep_manifest import checked_manifest
from scratchworld_dist.sweep import load_sweep_config
from tests.conftest import REPO
from workers.actor import JobWorker
from workers.contract import HarnessFingerprint, fingerprint
from workers.kinds import KindRegistryError, claimed_parts, kind_fingerprint, kind_named, kind_of, worker_kinds
from workers.node import code_parts, harness_fingerprint

WORKERS = REPO / "workers"
KINDS = ("tasks", "drag", "perception", "audit")


def edited(tree: Path, relative: str) -> dict[str, str]:
    """The code parts of ``tree`` after a harmless edit to one of its files (a comment appended)."""
    path = tree / relative
    path.write_text(path.read_text() + "\n# edited\n")
    return code_parts(tree, REPO / "scratch-gui")


def digests(parts: dict[str, str]) -> dict[str, str]:
    full = fingerprint(parts)
    return {kind: kind_fingerprint(full, kind).digest for kind in KINDS}


def test_the_built_in_kinds_are_registered_light_and_own_their_specs() -> None:
    kinds = worker_kinds()
    assert set(kinds) >= set(KINDS)
    from workers.kinds.drag import DragSpec
    from workers.kinds.perception import PerceptionSpec
    from workers.kinds.tasks import EpisodeSpec, RegradeSpec

    assert [kind_of(spec_class.model_construct()).name for spec_class in (EpisodeSpec, RegradeSpec)] == ["tasks"] * 2
    assert kind_of(DragSpec.model_construct()) is kinds["drag"]
    assert kind_of(PerceptionSpec.model_construct()) is kinds["perception"]
    assert (kinds["tasks"].needs_browser, kinds["drag"].needs_browser, kinds["perception"].needs_browser) == (
        True,
        True,
        False,
    )
    with pytest.raises(KindRegistryError, match="'mutation' is not registered"):
        kind_named("mutation")
    with pytest.raises(KindRegistryError):
        kind_fingerprint(harness_fingerprint(), "mutation")


def test_an_edit_to_a_kind_changes_its_fingerprint_alone_and_a_core_edit_changes_all(tmp_path: Path) -> None:
    tree = tmp_path / "workers"
    shutil.copytree(WORKERS, tree, ignore=shutil.ignore_patterns("__pycache__"))
    before = digests(code_parts(tree, REPO / "scratch-gui"))
    assert len(set(before.values())) == len(KINDS)  # a digest per kind
    after_drag = digests(edited(tree, "kinds/drag/_runner.py"))
    assert after_drag["tasks"] == before["tasks"] and after_drag["perception"] == before["perception"]
    assert after_drag["drag"] != before["drag"]
    after_perception = digests(edited(tree, "kinds/perception/_scoring.py"))
    assert {k: after_perception[k] == after_drag[k] for k in KINDS} == {
        "tasks": True,
        "drag": True,
        "perception": False,
        "audit": True,
    }
    after_tasks = digests(edited(tree, "kinds/tasks/_runner.py"))
    assert {k: after_tasks[k] == after_perception[k] for k in KINDS} == {
        "tasks": False,
        "drag": True,
        "perception": True,
        "audit": True,
    }
    after_audit = digests(edited(tree, "kinds/audit/_kind.py"))
    assert {k: after_audit[k] == after_tasks[k] for k in KINDS} == {
        "tasks": True,
        "drag": True,
        "perception": True,
        "audit": False,
    }
    after_tasks = after_audit
    for core in (
        "editor/_editor.py",
        "agents/_coordinates.py",
        "actor/_browser.py",
        "evaluation/_evaluator.py",
        "kinds/_registry.py",
    ):
        now = digests(edited(tree, core))
        assert all(now[kind] != after_tasks[kind] for kind in KINDS), core
        after_tasks = now


def test_the_full_fingerprint_still_covers_every_kind(tmp_path: Path) -> None:
    """What nodes report and compare: all of workers/, whichever kind the edit belongs to."""
    tree = tmp_path / "workers"
    shutil.copytree(WORKERS, tree, ignore=shutil.ignore_patterns("__pycache__"))
    before = fingerprint(code_parts(tree, REPO / "scratch-gui"))
    after = fingerprint(edited(tree, "kinds/drag/_runner.py"))
    assert before.differences(after) == ["workers/kinds/drag/_runner.py"]
    assert kind_fingerprint(before, "drag").differences(kind_fingerprint(after, "drag")) == [
        "workers/kinds/drag/_runner.py"
    ]
    assert "workers/kinds/drag/_runner.py" not in kind_fingerprint(before, "tasks").parts


def with_edited_drag(harness: HarnessFingerprint) -> HarnessFingerprint:
    return fingerprint({**harness.parts, "workers/kinds/drag/_runner.py": "edited0000000000"})


def test_editing_drag_code_leaves_an_episode_run_resumable_and_a_drag_run_refuses(tmp_path: Path) -> None:
    ours = harness_fingerprint()
    theirs = with_edited_drag(ours)
    config = load_sweep_config(REPO / "configs" / "demo.yaml").model_copy(update={"output": tmp_path / "demo"})
    before, after = plan_run(config, ours), plan_run(config, theirs)
    assert [job.job_id for job in before.jobs] == [job.job_id for job in after.jobs]
    assert before.harness == after.harness == kind_fingerprint(ours, "tasks")
    run_dir = config.run_dir()
    run_dir.mkdir(parents=True)
    from scratchworld_dist.results._manifest import write_manifest

    write_manifest(run_dir, checked_manifest(before, run_dir, force=False))
    resumed = checked_manifest(after, run_dir, force=False)  # would raise RunDirError on another harness
    assert resumed.harness == before.harness

    drag = load_sweep_config(REPO / "configs" / "drag-demo.yaml")
    no_optional = drag.sections["drag"].model_copy(update={"optional_suites": []})
    drag = drag.model_copy(update={"output": tmp_path / "drag", "sections": {**drag.sections, "drag": no_optional}})
    drag_before, drag_after = plan_run(drag, ours), plan_run(drag, theirs)
    assert not {job.job_id for job in drag_before.jobs} & {job.job_id for job in drag_after.jobs}
    drag.run_dir().mkdir(parents=True)
    write_manifest(drag.run_dir(), checked_manifest(drag_before, drag.run_dir(), force=False))
    with pytest.raises(RunDirError, match=re.escape("workers/kinds/drag/_runner.py")):
        checked_manifest(drag_after, drag.run_dir(), force=False)


# --- the claims, against the imports ------------------------------------------------------------


def module_file(module: str) -> Path | None:
    path = REPO.joinpath(*module.split("."))
    if (path / "__init__.py").is_file():
        return path / "__init__.py"
    return path.with_suffix(".py") if path.with_suffix(".py").is_file() else None


def imported(module: str) -> set[str]:
    """The ``workers`` modules ``module`` imports anywhere (in functions too), with their packages."""
    path = module_file(module)
    assert path is not None, module
    named: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("workers"):
            named.add(node.module)
            named.update(f"{node.module}.{alias.name}" for alias in node.names)
        elif isinstance(node, ast.Import):
            named.update(alias.name for alias in node.names if alias.name.startswith("workers"))
    parts = {".".join(name.split(".")[:i]) for name in named for i in range(1, name.count(".") + 2)}
    return {name for name in parts if module_file(name) is not None}


def closure(starts: set[str], barred: set[str]) -> set[str]:
    """What ``starts`` import, transitively, not following into ``barred`` (the kinds' lazily imported runners)."""
    seen: set[str] = set()
    todo = list(starts)
    while todo:
        module = todo.pop()
        if module not in seen:
            seen.add(module)
            todo.extend(imported(module) - barred - seen)
    return seen


def part_of(module: str) -> str:
    path = module_file(module)
    assert path is not None
    return path.relative_to(REPO).as_posix()


def test_no_kind_claims_code_the_core_or_another_kind_imports() -> None:
    """A kind's folder is its own: neither the worker's core (the actor, the kinds' registry) nor another kind
    imports anything in it, and everything it claims is reached from its package."""
    kinds = worker_kinds()
    packages = {name: f"workers.kinds.{name}" for name in KINDS}
    core = closure({"workers.actor", "workers.kinds"}, set(packages.values()))
    for name in KINDS:
        claimed = claimed_parts(kinds[name])
        assert claimed == (f"workers/kinds/{name}/",), claimed  # one folder a kind
        others = closure({package for other, package in packages.items() if other != name}, {packages[name]})
        for module in sorted(core | others):
            assert not part_of(module).startswith(claimed), f"{name} claims {part_of(module)}, imported by others"
        own = {part_of(module) for module in closure({packages[name]}, set())}
        assert all(any(part.startswith(prefix) for part in own) for prefix in claimed), (name, claimed)


# --- a fourth kind, from a plugin ---------------------------------------------------------------

PLUGIN = """
from pydantic import BaseModel
from workers.contract import JobResult


class MutationSpec(BaseModel):
    job_id: str
    attempt: int = 1
    task_id: str
    timeout_s: float = 10
    harness: str | None = None


class MutationPayload(BaseModel):
    task_id: str


class MutationKind:
    name = "mutation"
    specs = (MutationSpec,)
    payloads = (MutationPayload,)
    code = ()
    needs_browser = False

    async def run(self, host, spec, payload):
        return JobResult(job_id=spec.job_id, attempt=spec.attempt, outcome="passed", stop_reason="done")


KIND = MutationKind()
"""


@pytest.fixture
def plugin(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    """An installed distribution registering a fourth kind (its dist-info names the entry point)."""
    site = tmp_path / "site"
    (site / "mutation_kind").mkdir(parents=True)
    (site / "mutation_kind" / "__init__.py").write_text(PLUGIN)
    info = site / "mutation_kind-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: mutation-kind\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[scratchworld.worker_kinds]\nmutation = mutation_kind:KIND\n")
    monkeypatch.syspath_prepend(str(site))
    yield site
    sys.modules.pop("mutation_kind", None)


async def test_a_plugin_registers_a_fourth_kind_that_the_worker_runs(plugin: Path) -> None:
    kinds = worker_kinds()
    assert set(kinds) == {*KINDS, "mutation"}
    from mutation_kind import MutationPayload, MutationSpec  # type: ignore[import-not-found]

    worker = JobWorker(worker_index=0)
    spec = MutationSpec(job_id="m1", task_id="t", harness=kind_fingerprint(harness_fingerprint(), "mutation").digest)
    result = await worker.run(spec, MutationPayload(task_id="t"))
    assert (result.job_id, result.outcome) == ("m1", "passed"), result.error_message
    # It claims no code, so its digest is the core plus every other kind's code, and the others' do not move.
    assert kind_fingerprint(harness_fingerprint(), "tasks") == kind_fingerprint(harness_fingerprint(), "tasks", kinds)
    refused = await worker.run(
        spec.model_copy(update={"harness": worker.kind_harness("tasks")}), MutationPayload(task_id="t")
    )
    assert refused.error_class == "harness_mismatch"


def test_a_plugin_kind_that_claims_a_built_in_spec_is_refused(plugin: Path) -> None:
    source = plugin / "mutation_kind" / "__init__.py"
    source.write_text(
        source.read_text().replace(
            "specs = (MutationSpec,)", "specs = (__import__('workers.kinds.drag').kinds.drag.DragSpec,)"
        )
    )
    with pytest.raises(KindRegistryError, match="both claim DragSpec"):
        worker_kinds()
