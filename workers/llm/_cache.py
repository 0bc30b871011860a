"""The model-call cache: successful replies filed under their full request, replayed at no cost.

A reply is filed under the SHA-256 of canonical JSON of everything that decides it (``request_key``;
``ModelClient`` assembles it: the model's identity, the seed, every keyword sent to LiteLLM but the
API key, every message with its images in full, and LiteLLM's version), so a changed request is a
different key and can never be answered by another request's reply. Each entry is one JSON file,
``<dir>/<key[:2]>/<key>.json``, written under a unique temporary name and renamed into place, so
runs and nodes can share one folder (e.g. on a shared filesystem) without a lock: concurrent
writers of a key write the same answer. An entry that cannot be read, does not validate, or names
another key is a miss with a warning, never a crash or a wrong answer; the next successful call
overwrites it. Entries hold the reply and its usage, never the request's secrets.

LiteLLM's own cache does not fit: its disk backend is SQLite with pickled values (not safe on a
shared filesystem, and a hostile entry would run code on load), it is one global setting per
process rather than per sweep, and its hits would still pass through our rate limiter and retries.
"""

from __future__ import annotations

import asyncio
import errno
import hashlib
import json
import logging
import os
import secrets
import stat
from pathlib import Path
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from workers.contract import ModelSpec
from workers.llm._litellm import takes_seed

logger = logging.getLogger(__name__)

CACHE_FORMAT = 1
"""Version of the key's contents and the entry's shape; a change makes every old entry a miss."""

MAX_ENTRY_BYTES = 8 * 1024 * 1024
"""The largest entry read: replies are kilobytes, so a bigger file is not one of ours."""


class CacheEntry(BaseModel):
    """One stored reply: what the model answered and what the original call used."""

    model_config = ConfigDict(frozen=True, extra="forbid")

    format: Literal[1]
    key: str = Field(pattern=r"^[0-9a-f]{64}$")
    """The request key the entry answers; checked against the key asked for."""

    model: str
    """The LiteLLM model string called (for a person reading the folder)."""

    seed: int | None
    text: str
    input_tokens: int = Field(ge=0)
    output_tokens: int = Field(ge=0)
    cost_usd: float = Field(ge=0)
    """What the original call cost (a replay costs nothing)."""

    answered_by: str
    """The model the provider said answered."""

    finish_reason: str | None = None
    reasoning: str | None = None
    """The reasoning the provider returned besides the reply (None: none, or an entry stored before it was kept)."""

    stored_at: float


def uncacheable(spec: ModelSpec, seeded: bool = True) -> str | None:
    """Why this model's replies may not be cached, or None: with a temperature above 0 (an unset one is
    the provider's default, 1 for most) and no seed sent, one sampled reply would stand in for all.
    ``seeded``: the calls pass a seed (episodes always do)."""
    temperature = spec.temperature if spec.temperature is not None else spec.params.get("temperature")
    if temperature == 0 or (seeded and takes_seed(spec.model)):
        return None
    said = (
        "temperature unset (the provider's default, usually 1)" if temperature is None else f"temperature {temperature}"
    )
    unseeded = f"{spec.model} takes no seed" if seeded else "no seed is given"
    return (
        f"model {spec.name}: {said} and {unseeded}, so a cached reply would replay one sample "
        "as the model's answer; set temperature: 0 or turn model_cache off"
    )


def request_key(request: dict[str, Any]) -> str | None:
    """SHA-256 of the request as canonical JSON; None when it is not plain JSON (then it is not cached)."""
    try:
        canonical = json.dumps(request, sort_keys=True, separators=(",", ":"), allow_nan=False)
    except (TypeError, ValueError):
        return None
    return hashlib.sha256(canonical.encode()).hexdigest()


class ModelCache:
    """One cache folder; safe to share between tasks, processes and nodes."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder

    def path(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.json"

    async def get(self, key: str) -> CacheEntry | None:
        """The entry stored for ``key``, or None (absent, or not a valid entry for it: warned)."""
        return await asyncio.to_thread(self._read, key)

    async def put(self, entry: CacheEntry) -> None:
        """Store ``entry``; a folder that cannot take it is warned about, never an error of the call."""
        await asyncio.to_thread(self._write, entry)

    def _read(self, key: str) -> CacheEntry | None:
        path = self.path(key)
        try:
            data = _read_regular_file(path, MAX_ENTRY_BYTES)
        except FileNotFoundError:
            return None
        except OSError as exc:
            logger.warning("model cache: cannot read %s (%s); calling the model", path, exc.strerror or exc)
            return None
        try:
            entry = CacheEntry.model_validate_json(data)
        except ValidationError as exc:
            first = exc.errors()[0]
            where = ".".join(str(part) for part in first["loc"]) or "entry"
            logger.warning(
                "model cache: %s is not a valid entry (%s: %s); calling the model", path, where, first["msg"]
            )
            return None
        if entry.key != key:
            logger.warning("model cache: %s holds the entry of another request; calling the model", path)
            return None
        return entry

    def _write(self, entry: CacheEntry) -> None:
        path = self.path(entry.key)
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            _write_atomic(path, entry.model_dump_json().encode())
        except OSError as exc:
            logger.warning("model cache: cannot store %s (%s)", path, exc.strerror or exc)


def _read_regular_file(path: Path, limit: int) -> bytes:
    """At most ``limit`` bytes of a regular file (not following a symlink); a FIFO or device is refused
    at once, and a longer file is refused rather than read to the end."""
    descriptor = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOFOLLOW)
    with os.fdopen(descriptor, "rb") as handle:
        if not stat.S_ISREG(os.fstat(descriptor).st_mode):
            raise OSError(errno.EINVAL, "not a regular file", str(path))
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise OSError(errno.EFBIG, f"larger than {limit} bytes", str(path))
    return data


def _write_atomic(path: Path, data: bytes) -> None:
    """A uniquely named temporary file renamed over ``path``: readers on any node see a whole entry or none,
    and writers of the same key never share a temporary file."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        with tmp.open("xb") as handle:
            handle.write(data)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
