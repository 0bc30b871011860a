"""Which tests of a suite are known to be unstable: a flake run's findings, kept as data a user can read.

``scratchworld flakes --stability-out FILE`` writes what it found; the harness reads it back to mark
verdicts of unstable tests wherever a user meets them (``validate``, reports, the viewer, ``compare``).
An upstream clone is read in place and never written to, so its data ships with this package
(``stability/upstream.json``); a suite of ours keeps its own ``stability.json`` beside ``suite.json``.

Findings hold for the scripts they were made with: each checked task's scripts are digested, and a
task whose scripts changed since is not checked (its tests are neither stable nor unstable).
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable
from functools import cache
from pathlib import Path
from typing import Literal

from pydantic import BaseModel, ConfigDict, ValidationError

from scratchworld_dist._errors import SuiteError, validation_summary
from scratchworld_dist._files import read_file
from scratchworld_dist.suites._task import Suite, Task

PACKAGED_DIR = Path(__file__).with_name("stability")
SUITE_STABILITY_FILE = "stability.json"
"""A suite of ours keeps its data here, beside ``suite.json``."""


class UnstableTest(BaseModel):
    """A test whose verdict changed under a perturbation that must not change it."""

    __test__ = False  # not a pytest test class, despite the name
    model_config = ConfigDict(frozen=True)

    task_id: str
    test: str
    projects: list[str]
    """The projects (golden, initial) in which it flipped."""
    baseline: str
    """Its baseline verdict in each of those, e.g. ``golden pass``."""
    flipped: int
    runs: int
    """Runs of the flake run besides the baselines, over the projects in ``projects``."""
    flipped_by: list[str]
    """The perturbations (axes) that changed it: ``phase``, ``lateness``, ``clock``..."""
    flips: list[str]
    """Each flipping run, ``<project>: <run> → <verdict>``."""
    passes_at: str | None = None
    """Its passing band on the lateness axis (frame rates), when that axis ran."""

    def note(self) -> str:
        """One line for people: what changes it and where it passes."""
        text = f"unstable: {', '.join(self.flipped_by)} changed it in {self.flipped} of {self.runs} runs"
        return text + (f"; passes at {self.passes_at}" if self.passes_at else "")


class SuiteStability(BaseModel):
    """A suite's known test stability (``stability.json``): what was checked, how, and what is unstable."""

    model_config = ConfigDict(frozen=True)

    suite: str
    """The suite's name when it was checked."""
    command: str
    """The command that made the data (run it again to regenerate it)."""
    made_on: str
    """The date, ``YYYY-MM-DD``."""
    profile: str
    clock: str
    """The baseline's clock; the clock axis ran the other one."""
    render: str
    page: str
    axes: list[str]
    runs_per_axis: int
    evaluations: int
    tests_checked: int
    scripts: dict[str, str]
    """Each checked task's id and the digest of its evaluation script and helper (``scripts_digest``)."""
    unstable: list[UnstableTest]

    def standing(self, task: Task) -> Literal["checked", "unchecked", "changed"]:
        """Whether the data covers ``task`` as it is now: checked, never checked, or its scripts changed since."""
        digest = self.scripts.get(task.id)
        if digest is None:
            return "unchecked"
        return "checked" if digest == scripts_digest(task) else "changed"

    def unstable_tests(self, task: Task) -> dict[str, UnstableTest] | None:
        """The unstable tests of ``task`` by name ({} when none is), or None when the data does not cover it."""
        if self.standing(task) != "checked":
            return None
        return {row.test: row for row in self.unstable if row.task_id == task.id}

    def unstable_notes(self, task: Task) -> dict[str, str] | None:
        """``unstable_tests`` as each test's one-line note, for rows and manifests."""
        found = self.unstable_tests(task)
        return None if found is None else {name: test.note() for name, test in found.items()}


def scripts_digest(task: Task) -> str:
    """A digest of what judges the task: its evaluation script and its helper."""
    digest = hashlib.sha256(read_file(task.evaluation_script))
    if task.helper_script is not None:
        digest.update(b"\0" + read_file(task.helper_script))
    return digest.hexdigest()[:16]


def stability_file(suite: Suite) -> Path:
    """Where the suite's known stability is kept: beside a suite of ours, or in this package for upstream."""
    if suite.kind == "upstream":
        return PACKAGED_DIR / "upstream.json"
    return suite.root / SUITE_STABILITY_FILE


def read_stability(path: Path) -> SuiteStability:
    """The data at ``path``; ``SuiteError`` naming the file when it is unreadable or malformed."""
    try:
        return SuiteStability.model_validate_json(read_file(path))
    except OSError as exc:
        raise SuiteError(f"{path}: unreadable test stability file: {exc.strerror or exc}") from exc
    except ValidationError as exc:
        raise SuiteError(f"{path}: not a test stability file: {validation_summary(exc)}") from exc


def known_stability(suite: Suite) -> SuiteStability | None:
    """The suite's known test stability, or None when it has none."""
    path = stability_file(suite)
    if not path.is_file():
        return None
    return _read_cached(path, path.stat().st_mtime_ns)


@cache
def _read_cached(path: Path, mtime_ns: int) -> SuiteStability:
    return read_stability(path)


class StabilityMarks(BaseModel):
    """What a suite's known test stability says of a selection of its tasks, copied into a run's manifest so
    that its reports mark the tests known to be unstable when it was made, whatever the file says later."""

    model_config = ConfigDict(frozen=True)

    source: str
    """The stability file it came from."""
    made_on: str
    checked: list[str]
    """The selected tasks the data covers (their scripts unchanged since)."""
    unstable: dict[str, dict[str, str]]
    """Task id → its unstable tests, each with its note."""

    def is_unstable(self, task_id: str, test: str) -> bool | None:
        """True: known unstable; False: checked and stable; None: its task was not checked."""
        if task_id not in self.checked:
            return None
        return test in self.unstable.get(task_id, {})


def stability_marks(suite: Suite, tasks: Iterable[Task]) -> StabilityMarks | None:
    """The suite's known test stability restricted to ``tasks`` (None when the suite has none)."""
    known = known_stability(suite)
    if known is None:
        return None
    checked, unstable = [], {}
    for task in tasks:
        notes = known.unstable_notes(task)
        if notes is None:
            continue
        checked.append(task.id)
        if notes:
            unstable[task.id] = notes
    return StabilityMarks(source=str(stability_file(suite)), made_on=known.made_on, checked=checked, unstable=unstable)
