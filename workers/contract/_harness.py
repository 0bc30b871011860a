"""The harness fingerprint and the nodes that report one: what job ids, rows and manifests record.

The digest is computed on each node (``workers.node``); here are the values that cross process
and host boundaries, and how two of them are compared.
"""

from __future__ import annotations

import hashlib
import json

from pydantic import BaseModel, ConfigDict

ENVIRONMENT_PARTS = ("editor:bundle", "browser:chromium")
"""The parts a node's installation decides rather than its checkout."""


class HarnessFingerprint(BaseModel):
    """A digest over named parts (files by path, ``package:``, ``editor:``, ``browser:``), and the parts."""

    model_config = ConfigDict(frozen=True)

    digest: str
    """16 hex digits over every part; what job ids and rows carry."""

    parts: dict[str, str]
    """Each part's own digest (files) or version (packages, browser), for saying what differs."""

    def differences(self, other: HarnessFingerprint) -> list[str]:
        """The parts that differ between two fingerprints, in order."""
        names = sorted(set(self.parts) | set(other.parts))
        return [name for name in names if self.parts.get(name) != other.parts.get(name)]

    @property
    def code(self) -> HarnessFingerprint:
        """The fingerprint of the checkout alone (what a driver without browsers can compute)."""
        return fingerprint({k: v for k, v in self.parts.items() if k not in ENVIRONMENT_PARTS})

    @property
    def environment(self) -> dict[str, str]:
        return {k: v for k, v in self.parts.items() if k in ENVIRONMENT_PARTS}

    def with_environment(self, environment: dict[str, str]) -> HarnessFingerprint:
        return fingerprint({**self.code.parts, **environment})

    def without(self, prefixes: tuple[str, ...]) -> HarnessFingerprint:
        """The fingerprint over the parts whose names start with none of ``prefixes`` (another kind's code)."""
        if not any(name.startswith(prefixes) for name in self.parts):
            return self
        return fingerprint({k: v for k, v in self.parts.items() if not k.startswith(prefixes)})


def fingerprint(parts: dict[str, str]) -> HarnessFingerprint:
    canonical = json.dumps(parts, sort_keys=True, separators=(",", ":")).encode()
    return HarnessFingerprint(digest=hashlib.sha256(canonical).hexdigest()[:16], parts=parts)


def describe_differences(ours: HarnessFingerprint, theirs: HarnessFingerprint, limit: int = 8) -> str:
    """``workers/editor/_editor.py, package:litellm (+3 more)``: the first few differing parts."""
    differing = ours.differences(theirs)
    shown = ", ".join(differing[:limit])
    return shown + (f" (+{len(differing) - limit} more)" if len(differing) > limit else "")


class NodeReport(BaseModel):
    """One node as it describes itself (computed on the node, from its own checkout and installation)."""

    model_config = ConfigDict(frozen=True)

    node_id: str
    hostname: str
    address: str
    """The node's IP address as Ray knows it."""

    harness_dir: str
    """The checkout this node's workers run from."""

    harness: HarnessFingerprint
    browser_slots: int = 0

    @property
    def name(self) -> str:
        """How messages name the node: host, address, Ray node id and checkout."""
        return f"{self.hostname} ({self.address}, node {self.node_id[:8]}, harness at {self.harness_dir})"

    def summary(self) -> NodeSummary:
        return NodeSummary(
            node_id=self.node_id,
            hostname=self.hostname,
            address=self.address,
            harness_dir=self.harness_dir,
            harness=self.harness.digest,
            editor=self.harness.parts.get("editor:bundle", "?"),
            browser=self.harness.parts.get("browser:chromium", "?"),
            browser_slots=self.browser_slots,
        )


class NodeSummary(BaseModel):
    """A node as the run manifest records it."""

    node_id: str
    hostname: str
    address: str
    harness_dir: str
    harness: str
    editor: str
    browser: str
    browser_slots: int
