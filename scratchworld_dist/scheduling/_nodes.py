"""Checking a cluster's nodes before any job is sent: same harness code, same editor, same browser.

Each node with browser slots describes itself in a Ray task pinned to it (``describe_node``);
every node must run the driver's code, and all of them the same editor bundle and Chromium.
The harness jobs are planned under is then the driver's code with the nodes' environment.
"""

from __future__ import annotations

import ray
from ray.exceptions import GetTimeoutError, RayError
from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

from scratchworld_dist.scheduling._ray_runtime import BROWSER_RESOURCE, RayUnavailableError
from workers.contract import HarnessFingerprint, NodeReport, describe_differences
from workers.node import describe_node

INSPECT_TIMEOUT_S = 120.0
"""How long a node may take to describe itself (it may first have to start a Python worker)."""


class NodeMismatchError(RayUnavailableError):
    """A node runs other code, or renders with another editor or browser, than the run needs."""


def inspect_nodes(timeout_s: float = INSPECT_TIMEOUT_S) -> list[NodeReport]:
    """Every alive node with browser slots, as it describes itself."""
    nodes = [n for n in ray.nodes() if n.get("Alive") and n.get("Resources", {}).get(BROWSER_RESOURCE, 0) > 0]
    describe = ray.remote(describe_node)
    pending = {
        describe.options(
            num_cpus=0, scheduling_strategy=NodeAffinitySchedulingStrategy(node["NodeID"], soft=False)
        ).remote(node["NodeID"], node["NodeManagerAddress"], int(node["Resources"][BROWSER_RESOURCE])): node
        for node in nodes
    }
    ready, silent = ray.wait(list(pending), num_returns=len(pending), timeout=timeout_s)
    if silent:
        names = ", ".join(f"{pending[ref]['NodeManagerAddress']} (node {pending[ref]['NodeID'][:8]})" for ref in silent)
        raise NodeMismatchError(f"node(s) {names} did not describe themselves within {timeout_s:g} s")
    try:
        return [ray.get(ref) for ref in ready]
    except (RayError, GetTimeoutError) as exc:
        raise NodeMismatchError(f"a node could not describe itself: {str(exc).splitlines()[0][:300]}") from exc


def agreed_harness(reports: list[NodeReport], driver: HarnessFingerprint) -> HarnessFingerprint:
    """The driver's code with the nodes' common environment; raises naming every node that differs."""
    problems = [
        f"{report.name} runs other code than the driver (differs in {_code_differences(driver, report)})"
        for report in reports
        if report.harness.code.digest != driver.code.digest
    ]
    reference = reports[0]
    problems += [
        f"{report.name} renders with {_environment(report)}, {reference.name} with {_environment(reference)}"
        for report in reports[1:]
        if report.harness.environment != reference.harness.environment
    ]
    if problems:
        raise NodeMismatchError(
            "refusing nodes that would produce verdicts for another harness: "
            + "; ".join(problems)
            + ". Install the same checkout on every node (see docs/cluster.md) or remove them"
        )
    return driver.with_environment(reference.harness.environment)


def _code_differences(driver: HarnessFingerprint, report: NodeReport) -> str:
    return describe_differences(driver.code, report.harness.code)


def _environment(report: NodeReport) -> str:
    parts = report.harness.environment
    return f"editor {parts.get('editor:bundle', '?')} and {parts.get('browser:chromium', '?')}"
