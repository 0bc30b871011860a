"""``manifest.json``: what a run directory holds, so its results can be trusted and compared."""

from __future__ import annotations

import json
import os
import platform
import socket
import subprocess
from collections.abc import Callable, Iterable, Sequence
from datetime import UTC, datetime
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import TYPE_CHECKING, Any

from pydantic import BaseModel, Field, ValidationError

from scratchworld_dist._errors import NotARunDirError, RunDirError, validation_summary
from scratchworld_dist.results._schema import CONTINUABLE_SCHEMAS
from scratchworld_dist.sweep import SuiteInfo
from workers.contract import HarnessFingerprint, NodeSummary, Preflight, describe_differences

if TYPE_CHECKING:  # the rows module imports the sweep's plan, which needs none of this
    from scratchworld_dist.results._rows import JobRow

MANIFEST_NAME = "manifest.json"
_PACKAGES = ("scratchworld-dist", "ray", "pyarrow", "playwright", "pydantic", "litellm")


class Session(BaseModel):
    """One invocation of ``scratchworld run`` on this directory."""

    started_at: datetime
    finished_at: datetime | None = None
    host: str
    pid: int
    planned: int
    submitted: int = 0
    budget_stop: str | None = None
    """Why this session left jobs unstarted: the sweep's model spend reached its budget."""

    nodes: list[NodeSummary] = Field(default_factory=list)
    """The nodes with browsers this session ran on (checked to run the run's harness)."""

    preflight: Preflight | None = None
    """What the models its jobs call answered before any job started (None: they call none)."""

    @classmethod
    def begin(cls, planned: int, nodes: list[NodeSummary]) -> Session:
        """A session of this process starting now, with ``planned`` jobs to run."""
        return cls(started_at=now(), host=socket.gethostname(), pid=os.getpid(), planned=planned, nodes=nodes)


class RegradeInfo(BaseModel):
    """What a regrade run re-evaluated (its source run) and under which conditions."""

    source_run: str
    """The source run directory, resolved."""

    source_run_name: str
    source_harness: str | None
    """The source run's harness digest (its agents ran under it)."""

    source_config_hash: str
    suite: SuiteInfo
    """The suite whose evaluation scripts made the new verdicts."""

    profile: str
    clock: str
    render: str | None = None
    """When the regrade's evaluations drew the stage (None in regrades made before the choice existed)."""

    evaluation_page: str | None = None
    """The page the regrade's evaluations ran in (None in regrades made before the bare page existed: the editor)."""

    regraded_jobs: int
    """Source jobs whose stored final project is regraded (one job each here)."""

    without_project: int
    """Source jobs that stored no final project (e.g. an error before the editor opened): not regraded."""


class TrackerRuns(BaseModel):
    """Which experiment-tracker runs hold this run (``loggers:``), so a resumed run continues them."""

    key: str
    """The run's own key (hex), chosen by its first session with a tracker: W&B's run id, MLflow's
    ``scratchworld.run_key`` tag (found again even when the driver died before it recorded MLflow's id)."""

    runs: dict[str, str] = Field(default_factory=dict)
    """Each tracker's run id, by tracker name, as the last session that reached it recorded it."""


class RunManifest(BaseModel):
    run_name: str
    schema_version: int
    harness: HarnessFingerprint | None = None
    """The fingerprint of the code and editor the run's jobs are planned for (None: an older run)."""

    config: dict[str, Any]
    config_hash: str
    suite: SuiteInfo
    planned_jobs: int
    """Size of the job matrix; coverage is measured against it."""

    packages: dict[str, str] = Field(default_factory=dict)
    git_commit: str | None = None
    sessions: list[Session] = Field(default_factory=list)
    regrade: RegradeInfo | None = None
    """Set for a run made by ``scratchworld regrade``: its source and the new conditions (None otherwise)."""

    tags: dict[str, str] = Field(default_factory=dict)
    """The run's labels (``--tag key=value``, the config's ``tags``), those of every session; reports and exports
    carry them."""

    trackers: TrackerRuns | None = None
    """The experiment-tracker runs its sessions reported to (None: no session had a tracker)."""

    def is_current(self, suite_hash: str, harness: str | None) -> bool:
        """Whether a row of this suite and harness belongs to the run as it stands (others are stale)."""
        return suite_hash == self.suite.hash and harness == (self.harness.digest if self.harness else None)

    def current_rows(self, rows: Iterable[JobRow]) -> list[JobRow]:
        """The ``rows`` that belong to the run as it stands (``is_current``); the others are stale."""
        return [r for r in rows if self.is_current(r.suite_hash, r.harness_fingerprint)]

    @property
    def started_at(self) -> datetime | None:
        return self.sessions[0].started_at if self.sessions else None

    @property
    def finished_at(self) -> datetime | None:
        return self.sessions[-1].finished_at if self.sessions else None


def now() -> datetime:
    return datetime.now(tz=UTC)


def package_versions() -> dict[str, str]:
    found = {"python": platform.python_version()}
    for name in _PACKAGES:
        try:
            found[name] = version(name)
        except PackageNotFoundError:
            continue
    return found


def git_commit(path: Path) -> str | None:
    """The checkout's commit (with ``-dirty`` when it has local changes), if it is a git checkout."""
    try:
        out = subprocess.run(
            ["git", "describe", "--always", "--dirty", "--abbrev=40"],
            cwd=path,
            capture_output=True,
            text=True,
            timeout=10,
            check=True,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    return out.stdout.strip() or None


def require_manifest(run_dir: Path) -> RunManifest:
    """The manifest of ``run_dir``; ``RunDirError`` when the folder is missing or not a run directory."""
    if not run_dir.is_dir():
        raise NotARunDirError(run_dir, "no such folder")
    manifest = read_manifest(run_dir)
    if manifest is None:
        raise NotARunDirError(run_dir, f"no {MANIFEST_NAME} in it")
    return manifest


def read_manifest(run_dir: Path) -> RunManifest | None:
    path = run_dir / MANIFEST_NAME
    if not path.exists():
        return None
    try:
        return RunManifest.model_validate_json(path.read_bytes())
    except OSError as exc:
        raise RunDirError(f"{path}: unreadable run manifest: {exc.strerror or exc}") from exc
    except ValidationError as exc:
        raise RunDirError(f"{path}: not a run manifest: {validation_summary(exc)}") from exc


def write_manifest(run_dir: Path, manifest: RunManifest) -> None:
    """Replace the manifest atomically: readers see the old or the new one, never half."""
    path = run_dir / MANIFEST_NAME
    tmp = path.with_name(f".{MANIFEST_NAME}.{os.getpid()}.tmp")
    try:
        tmp.write_text(json.dumps(manifest.model_dump(mode="json"), indent=2) + "\n", encoding="utf-8")
        os.replace(tmp, path)
    except OSError as exc:
        raise RunDirError(f"{path}: cannot write the run manifest: {exc.strerror or exc}") from exc


def continued(
    run_dir: Path,
    fresh: RunManifest,
    *,
    force: bool,
    kind: str,
    config_label: str,
    also: Sequence[tuple[str, object, object]] = (),
    config_hash_of: Callable[[RunManifest], str] | None = None,
) -> RunManifest:
    """``fresh``, carrying the sessions of the manifest ``run_dir`` already holds.

    A directory holding results of another ``kind`` (``also``, then the config hash named ``config_label``,
    the suite's content, the result schema beyond ``CONTINUABLE_SCHEMAS`` or the harness differ) is refused,
    naming what differs, unless ``force``: its rows are then kept and reported as stale. ``config_hash_of`` hashes
    the old manifest's config as ``fresh`` was hashed (default: the hash it recorded).
    """
    old = read_manifest(run_dir)
    if old is None:
        return fresh
    checks = [
        *also,
        (config_label, config_hash_of(old) if config_hash_of else old.config_hash, fresh.config_hash),
        ("suite content", old.suite.hash, fresh.suite.hash),
    ]
    if not {old.schema_version, fresh.schema_version} <= CONTINUABLE_SCHEMAS:
        checks.append(("result schema", old.schema_version, fresh.schema_version))
    changes = [f"{what} {before} -> {after}" for what, before, after in checks if before != after]
    if fresh.harness is not None:
        changes += harness_changes(old.harness, fresh.harness)
    if changes and not force:
        raise RunDirError(
            f"{run_dir} holds results of another {kind} ({'; '.join(changes)}): choose another --out, or pass "
            "--force to continue here (older rows are kept and reported as stale)"
        )
    return fresh.model_copy(update={"sessions": old.sessions})


def harness_changes(old: HarnessFingerprint | None, new: HarnessFingerprint) -> list[str]:
    """How the harness of a run directory differs from this one, naming the files (empty: the same)."""
    if old is None:
        return [f"harness fingerprint (none recorded) -> {new.digest}"]
    if old.digest == new.digest:
        return []
    return [f"harness fingerprint {old.digest} -> {new.digest} (differs in {describe_differences(old, new)})"]
