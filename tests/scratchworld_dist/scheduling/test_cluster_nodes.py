"""A real cluster of `ray start` processes: the head holds no browsers, worker nodes run from other checkouts.

The head is started from this repository with ``{"browser": 0}``; worker nodes are started from
copies of the checkout in other directories (their Python imports the copy: ``PYTHONPATH``, as
a node installed from another clone would), with token authentication on, as Ray 2.60 does once
a token exists. A node from an identical copy runs real browser jobs; a node whose copy differs
in one file is refused by name before any job is sent. Every node listens on 127.0.0.1 only
(``tests/support/ray_loopback.py``).
"""

from __future__ import annotations

import shutil
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest
import yaml

from scratchworld_dist.results import RunStore, read_manifest
from scratchworld_dist.scheduling._nodes import NodeMismatchError, agreed_harness
from tests.conftest import REPO, copy_page_files, link_installed_packages
from tests.support.ray_cluster import Cluster
from tests.support.sweep_driver import SCRATCHWORLD
from workers.contract import NodeReport
from workers.kinds import kind_fingerprint
from workers.node import OWN_FILES, harness_fingerprint
from workers.node._fingerprint import EDITOR_LOCK_FILES

pytestmark = [pytest.mark.ray, pytest.mark.browser]

TASKS = ["sum_two_numbers", "quiz_score", "bouncing_ball_stuck"]


def checkout_copy(target: Path) -> Path:
    """The harness as another clone would hold it: sources copied, the npm installs linked."""
    for package in ("workers", "scratchworld_dist"):
        shutil.copytree(REPO / package, target / package, ignore=shutil.ignore_patterns("__pycache__"))
    copy_page_files(target / "scratch-gui", (*OWN_FILES, *EDITOR_LOCK_FILES))
    link_installed_packages(target / "scratch-gui")
    return target


@pytest.fixture
def cluster(tmp_path: Path) -> Iterator[Cluster]:
    running = Cluster(tmp_path)
    try:
        running.head()
        yield running
    finally:
        running.stop()


def sweep(tmp_path: Path, cluster: Cluster, name: str) -> Path:
    config = {
        "name": name,
        "suite": str(REPO / "tasks"),
        "agent": "oracle",
        "tasks": {"ids": TASKS},
        "output": str(tmp_path / name),
        "ray": {"address": cluster.address, "connect_timeout_s": 60},
        "limits": {"pages_per_worker": 1, "episode_timeout_s": 300},
    }
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump(config))
    return path


def run(config: Path, cluster: Cluster) -> subprocess.CompletedProcess[str]:
    """The driver, started outside any checkout: Ray puts the driver's working directory first on
    every worker's path, which on this one machine would be this repository."""
    return subprocess.run(
        [SCRATCHWORLD, "run", str(config)],
        cwd=config.parent,
        env=cluster.env(),
        capture_output=True,
        text=True,
        timeout=900,
    )


@pytest.mark.slow
@pytest.mark.timeout(2 * 900 + 300)  # two runs, each bounded at 900 s, after the cluster's start
def test_a_node_from_another_checkout_runs_jobs_and_a_differing_one_is_refused(
    tmp_path: Path, cluster: Cluster
) -> None:
    same = checkout_copy(tmp_path / "clone-b")
    cluster.node(same, browsers=2)

    done = run(sweep(tmp_path, cluster, "first"), cluster)
    assert done.returncode == 0, done.stdout + done.stderr
    rows = RunStore(tmp_path / "first").job_rows()
    assert sorted((row.task_id, row.outcome) for row in rows) == sorted((task, "passed") for task in TASKS)
    manifest = read_manifest(tmp_path / "first")
    assert manifest is not None and manifest.harness is not None
    (node,) = manifest.sessions[-1].nodes  # the head holds no browsers: every job ran on clone-b's node
    assert node.harness_dir == str(same) and node.browser_slots == 2
    assert {row.worker_node for row in rows} == {node.node_id}
    assert {row.harness_fingerprint for row in rows} == {manifest.harness.digest}
    # The driver's code, the node's (here identical) browser, planned under the episodes' kind.
    assert manifest.harness == kind_fingerprint(harness_fingerprint(), "tasks")

    other = checkout_copy(tmp_path / "clone-c")
    evaluation = other / "workers" / "evaluation" / "_evaluator.py"
    evaluation.write_text(evaluation.read_text() + "\n# a local change\n")
    cluster.node(other, browsers=1)
    refused = run(sweep(tmp_path, cluster, "second"), cluster)
    assert refused.returncode == 2
    message = refused.stderr.strip().splitlines()[-1]
    assert message.startswith("error: refusing nodes that would produce verdicts for another harness")
    assert f"harness at {other}" in message and "differs in workers/evaluation/_evaluator.py)" in message
    assert str(same) not in message  # the node that matches is not blamed
    assert "Traceback" not in refused.stderr
    assert not (tmp_path / "second" / "jobs").exists() or not RunStore(tmp_path / "second").job_rows()


def report(node_id: str, **environment: str) -> NodeReport:
    harness = harness_fingerprint()
    return NodeReport(
        node_id=node_id,
        hostname="host",
        address="10.0.0.1",
        harness_dir="/srv/checkout",
        harness=harness.with_environment({**harness.environment, **environment}),
    )


def test_nodes_must_agree_on_editor_and_browser() -> None:
    driver = harness_fingerprint()
    same = [report("aaaa1111"), report("bbbb2222")]
    assert agreed_harness(same, driver) == driver
    newer = report("cccc3333", **{"browser:chromium": "Chromium 157.0.1"})
    with pytest.raises(NodeMismatchError, match=r"host \(10.0.0.1, node cccc3333, .*Chromium 157.0.1"):
        agreed_harness([*same, newer], driver)
    # A driver without browsers plans under the nodes' environment, its own code.
    bare = driver.with_environment({"editor:bundle": "missing", "browser:chromium": "missing"})
    assert agreed_harness(same, bare) == driver
