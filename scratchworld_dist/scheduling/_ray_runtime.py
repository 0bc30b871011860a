"""Starting and joining Ray: a private local instance by default, a cluster by address.

Joining is checked first, within a bounded time, so that a wrong address fails in seconds with
one line naming it, instead of Ray retrying for minutes and printing its internal warnings: a
TCP connection to the address, then a GCS handshake in a child process (whose output is kept
from the user). Ray 2.60 clusters started on a machine that holds a token (any local Ray run
writes ``~/.ray/auth_token``) require token authentication; when the handshake is refused for
that reason, a driver holding a token (``~/.ray/auth_token``, ``RAY_AUTH_TOKEN``,
``RAY_AUTH_TOKEN_PATH``) presents it.
"""

from __future__ import annotations

import logging
import os
import socket
import subprocess
import sys
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path

import ray

from scratchworld_dist._errors import ScratchWorldError

BROWSER_RESOURCE = "browser"
"""Custom resource counting the editors a node may hold; each worker reserves one per page."""

LOCAL_OBJECT_STORE_BYTES = 512 * 2**20
"""Projects and scripts are small; a modest store keeps a laptop's /dev/shm free."""

_GCS_HANDSHAKE = "import sys\nfrom ray._raylet import GcsClient\nprint(GcsClient(address=sys.argv[1]).cluster_id)\n"
"""Run in a child process: Ray's client retries silently for minutes and logs to stderr."""


class RayUnavailableError(ScratchWorldError):
    """Ray could not be started or joined, or offers no browser slots."""


TOKEN_NOTICES = "ray._private.authentication.authentication_token_setup"
"""The logger of Ray's notice that token authentication is on (or off), printed by every ray.init."""

LOOPBACK = "127.0.0.1"
"""The address a private local Ray listens on and registers its node under."""


def _token_available() -> bool:
    path = os.environ.get("RAY_AUTH_TOKEN_PATH")
    return bool(os.environ.get("RAY_AUTH_TOKEN")) or Path(path or Path.home() / ".ray" / "auth_token").is_file()


def check_joinable(address: str, timeout_s: float) -> None:
    """Raise ``RayUnavailableError`` unless the cluster at ``address`` answers as a Ray cluster in time."""
    from ray._private.services import canonicalize_bootstrap_address

    deadline = time.monotonic() + timeout_s
    try:
        target = canonicalize_bootstrap_address(address) if not address.startswith("ray://") else address[6:]
    except (ConnectionError, ValueError) as exc:
        raise RayUnavailableError(f"cannot join the Ray cluster at {address}: {exc}") from exc
    if target is None:
        raise RayUnavailableError(f"cannot join the Ray cluster at {address}: no running cluster found")
    host, _, port = target.rpartition(":")
    where = address if target == address else f"{address} (Ray connects to {target})"
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=timeout_s):
            pass
    except (OSError, ValueError) as exc:
        if isinstance(exc, TimeoutError):
            reason = f"no answer within {timeout_s:g} s (ray.connect_timeout_s)"
        else:
            reason = getattr(exc, "strerror", None) or str(exc)
        raise RayUnavailableError(
            f"cannot reach the Ray cluster at {where}: {reason}; is `ray start --head` running there, "
            "and is its port open to this machine?"
        ) from exc
    if address.startswith("ray://"):
        return  # a Ray Client server: its own protocol, joined by ray.init
    failure = _handshake(target, deadline, os.environ)
    if failure == "auth" and "RAY_AUTH_MODE" not in os.environ and _token_available():
        # The cluster wants the token this machine holds: present it (only then: a driver in token
        # mode makes the workers of a cluster without authentication fail).
        failure = _handshake(target, deadline, {**os.environ, "RAY_AUTH_MODE": "token"})
        if failure is None:
            _enable_token_auth()
    if failure == "timeout":
        raise RayUnavailableError(
            f"{where} accepts connections but does not answer as a Ray cluster within {timeout_s:g} s "
            "(ray.connect_timeout_s)"
        )
    if failure == "auth":
        raise RayUnavailableError(
            f"the Ray cluster at {where} requires its authentication token: copy the head's token "
            "(`ray get-auth-token` there) to ~/.ray/auth_token here, or set RAY_AUTH_TOKEN"
        )
    if failure is not None:
        raise RayUnavailableError(f"{where} did not answer as a Ray cluster: {failure}")


def _enable_token_auth() -> None:
    """Token mode for this process from now on: Ray reads its config once, so it must be told to read it again."""
    from ray._private.authentication.authentication_token_setup import _enable_token_auth as enable

    enable()  # sets RAY_AUTH_MODE=token and re-initialises Ray's config (Ray 2.60)


def _handshake(target: str, deadline: float, env: Mapping[str, str]) -> str | None:
    """None when the GCS at ``target`` answers; else ``timeout``, ``auth`` or the child's last line."""
    try:
        done = subprocess.run(
            [sys.executable, "-c", _GCS_HANDSHAKE, target],
            capture_output=True,
            text=True,
            timeout=max(deadline - time.monotonic(), 1.0),
            env=dict(env),
        )
    except subprocess.TimeoutExpired:
        return "timeout"
    if done.returncode == 0:
        return None
    if "InvalidAuthToken" in done.stderr or "AuthenticationError" in done.stderr:
        return "auth"
    return (done.stderr.strip().splitlines() or ["no output"])[-1][:300]


def _start_private(slots: int) -> None:
    """A private Ray whose every server listens on 127.0.0.1 only; ``RayUnavailableError`` if it would not.

    Ray binds its servers to loopback only when the node's address is 127.0.0.1, and it swaps 127.0.0.1 for
    this machine's network address unless its cluster mode is off. ``RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=0``
    (set by this package) turns it off, but Ray reads it once, on import, and a user may have set it to 1:
    so the mode is off while this Ray starts, whatever the environment said, and the result is checked.
    """
    from ray._private import ray_constants

    cluster_mode = ray_constants.ENABLE_RAY_CLUSTER
    ray_constants.ENABLE_RAY_CLUSTER = False
    notices = logging.getLogger(TOKEN_NOTICES)
    level = notices.level
    notices.setLevel(
        logging.ERROR
    )  # "token authentication is enabled for this Ray cluster": ours serves this machine only
    try:
        ray.init(
            address="local",
            num_cpus=max(slots, os.cpu_count() or 1),
            resources={BROWSER_RESOURCE: slots},
            include_dashboard=False,
            log_to_driver=False,
            object_store_memory=LOCAL_OBJECT_STORE_BYTES,
            configure_logging=False,
            _node_ip_address=LOOPBACK,  # the private Ray serves this machine only
        )
    finally:
        ray_constants.ENABLE_RAY_CLUSTER = cluster_mode
        notices.setLevel(level)
    node = ray.util.get_node_ip_address()
    if node != LOOPBACK:  # a Ray that changed how it picks the address: fail closed, not open
        ray.shutdown()
        raise RayUnavailableError(f"the private Ray would listen on {node}, not on {LOOPBACK} only; not started")


@contextmanager
def ray_runtime(address: str | None, browser_slots: int | None, connect_timeout_s: float = 30.0) -> Iterator[int]:
    """Run Ray for the duration of the block; yields the number of browser slots available.

    Without an address a private instance is started (``address='local'``), even when a
    ``ray start`` cluster runs on this machine; with one, that cluster's nodes must declare
    ``--resources='{"browser": N}'``, and it must answer within ``connect_timeout_s``.
    """
    already = ray.is_initialized()
    if not already:
        try:
            if address is None:
                _start_private(browser_slots or os.cpu_count() or 1)
            else:
                check_joinable(address, connect_timeout_s)
                ray.init(address=address, log_to_driver=False, configure_logging=False)
        except (ConnectionError, ValueError, RuntimeError) as exc:
            raise RayUnavailableError(f"could not start or join Ray ({address or 'local'}): {exc}") from exc
    try:
        total = int(ray.cluster_resources().get(BROWSER_RESOURCE, 0))
        if total < 1:
            raise RayUnavailableError(
                f"the Ray cluster at {address} offers no {BROWSER_RESOURCE!r} resources: start its nodes with "
                f"ray start --resources='{{\"{BROWSER_RESOURCE}\": N}}' (N editors per node)"
            )
        yield total
    finally:
        if not already:
            ray.shutdown()


def worker_logs_dir() -> Path | None:
    """Where this machine's Ray workers write their logs (the same folder name on every node), once Ray is up."""
    node = getattr(ray._private.worker, "_global_node", None)  # Ray 2.60 keeps the session's node here
    logs = node.get_logs_dir_path() if node is not None else None
    return Path(logs) if logs else None
