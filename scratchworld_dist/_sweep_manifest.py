"""A sweep's manifest as ``run`` writes it, and the check that the run directory holds this sweep (or none): apart
from ``run_sweep`` so that ``plan`` says what ``run`` would refuse without importing Ray.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from pydantic import ValidationError

from scratchworld_dist.results import (
    SCHEMA_VERSION,
    RunManifest,
    continued,
    git_commit,
    package_versions,
    read_manifest,
)
from scratchworld_dist.sweep import RunPlan, SweepConfig


def config_hash(config: SweepConfig) -> str:
    """Hash of the fields that shape the job matrix; paths, execution limits, the model cache (a replay is
    the reply the same request got, so a run may turn it on or off), what is recorded besides the steps (a
    video), tags, trackers, other kinds' sections and what its own section lets change (``resume_free``: offline
    memory's source folder) may change freely. A config hashes
    the same whichever layout its file used (old configs' top-level keys are validated into their sections)."""
    sections: dict[str, object] = {kind: True for kind in config.sections if kind != config.benchmark}
    own = config.sections.get(config.benchmark)
    free = getattr(own, "resume_free", None)
    if free:
        sections[config.benchmark] = free
    pacing: dict[str, object] = {
        "sections": sections,
        "suite": True,
        "output": True,
        "storage": True,
        "limits": True,
        "ray": True,
        "model_cache": True,
        "record": True,
        "probe": True,
        "tags": True,
        "loggers": True,
        "llm": {"retry"},
        "models": {"__all__": {"rate_limits"}},
    }
    shaping = config.model_dump(mode="json", exclude=pacing)  # type: ignore[arg-type]
    return hashlib.sha256(json.dumps(shaping, sort_keys=True).encode()).hexdigest()[:16]


def checked_manifest(plan: RunPlan, run_dir: Path, force: bool, *, write_info: bool = True) -> RunManifest:
    """The manifest of ``plan``'s run in ``run_dir``, carrying the sessions of the one there; ``RunDirError``
    (naming what differs) when the directory holds another sweep, unless ``force``. Tags given now are added to
    those recorded before. ``write_info``: record this checkout's packages and commit (``plan`` skips it)."""
    fresh = RunManifest(
        run_name=plan.config.name,
        schema_version=SCHEMA_VERSION,
        harness=plan.harness,
        config=plan.config.model_dump(mode="json"),
        config_hash=config_hash(plan.config),
        suite=plan.suite,
        planned_jobs=len(plan.jobs),
        packages=package_versions() if write_info else {},
        git_commit=git_commit(Path(__file__).parent) if write_info else None,
    )
    manifest = continued(
        run_dir, fresh, force=force, kind="sweep", config_label="sweep config", config_hash_of=_hash_as_now
    )
    old = read_manifest(run_dir)
    tags = {**(old.tags if old is not None else {}), **plan.config.tags}
    return manifest.model_copy(update={"tags": tags, "trackers": old.trackers if old is not None else None})


def _hash_as_now(old: RunManifest) -> str:
    """An earlier run's config hashed as this code hashes (what counts may have changed since, e.g. other kinds'
    sections); its recorded hash when its config no longer reads."""
    try:
        return config_hash(SweepConfig.model_validate(old.config))
    except ValidationError:
        return old.config_hash
