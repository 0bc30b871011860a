"""A regrade run's manifest: the source's config under the new conditions, and where it came from.

Its ``config_hash`` covers the source and the conditions, so regrading into the same directory
under another suite, profile or clock is refused (unless forced), as ``scratchworld run`` refuses
another sweep.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from scratchworld_dist.kinds.tasks.regrade._plan import RegradePlan
from scratchworld_dist.results import (
    SCHEMA_VERSION,
    RegradeInfo,
    RunManifest,
    continued,
    git_commit,
    package_versions,
    read_manifest,
)
from scratchworld_dist.results.remote._view import shown_location


def regrade_manifest(plan: RegradePlan, out: Path, force: bool) -> RunManifest:
    """The manifest ``out`` gets; raises ``RunDirError`` when ``out`` holds another run, unless ``force``."""
    source = plan.source.manifest
    config = {
        **source.config,
        "name": out.name,
        "suite": plan.suite.root,
        "profile": plan.profile,
        "clock": plan.clock,
        "render": plan.render,
        "evaluation_page": plan.page,
        "output": str(out),
    }
    conditions = {
        "source": [str(plan.source.path), source.config_hash, source.harness.digest if source.harness else None],
        "suite": plan.suite.hash,
        "profile": plan.profile,
        "clock": plan.clock,
        "render": plan.render,
        "evaluation_page": plan.page,
        "project_limits": plan.project_limits.model_dump(mode="json"),
    }
    info = RegradeInfo(
        source_run=shown_location(plan.source.path),  # a remote source by its URL, not its local view
        source_run_name=source.run_name,
        source_harness=source.harness.digest if source.harness else None,
        source_config_hash=source.config_hash,
        suite=plan.suite,
        profile=plan.profile,
        clock=plan.clock,
        render=plan.render,
        evaluation_page=plan.page,
        regraded_jobs=len(plan.jobs),
        without_project=len(plan.source.without_project),
    )
    fresh = RunManifest(
        run_name=out.name,
        schema_version=SCHEMA_VERSION,
        harness=plan.harness,
        config=config,
        config_hash=hashlib.sha256(json.dumps(conditions, sort_keys=True).encode()).hexdigest()[:16],
        suite=plan.suite,
        planned_jobs=len(plan.jobs),
        packages=package_versions(),
        git_commit=git_commit(Path(__file__).parent),
        regrade=info,
    )
    old = read_manifest(out)
    source_before = old.regrade.source_run if old is not None and old.regrade else "(a sweep, not a regrade)"
    also = [("regrade of", source_before, info.source_run)] if old is not None else []
    return continued(out, fresh, force=force, kind="run", config_label="regrade conditions", also=also)
