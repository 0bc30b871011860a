"""Reads back what W&B wrote offline: the records of a ``run-<id>.wandb`` file (its log format: a 7-byte header,
then 32 KiB blocks of records, each with a checksum, a length, a type and a piece of a protobuf ``Record``)."""

from __future__ import annotations

import json
import struct
from pathlib import Path
from typing import Any

HEADER = b":W&B" + struct.pack("<HB", 0xBEE1, 0)
BLOCK = 32 * 1024
FULL, FIRST, MIDDLE, LAST = 1, 2, 3, 4


def records(path: Path) -> list[Any]:
    """The file's records, as ``wandb_internal_pb2.Record``."""
    from wandb.proto import wandb_internal_pb2

    data = path.read_bytes()
    assert data[: len(HEADER)] == HEADER, f"{path} is not a W&B run file"
    found, pieces, offset = [], b"", len(HEADER)
    while offset + 7 <= len(data):
        room = BLOCK - offset % BLOCK
        if room < 7:  # the block's tail is padding
            offset += room
            continue
        _, length, kind = struct.unpack("<IHB", data[offset : offset + 7])
        if kind == 0 and length == 0:
            offset += room
            continue
        pieces += data[offset + 7 : offset + 7 + length]
        offset += 7 + length
        if kind in (FULL, LAST):
            record = wandb_internal_pb2.Record()
            record.ParseFromString(pieces)
            found.append(record)
            pieces = b""
    return found


def offline_runs(root: Path) -> list[Path]:
    """The offline run files under a W&B ``dir``, oldest first."""
    return sorted((root / "wandb").glob("offline-run-*/run-*.wandb"))


def history(path: Path) -> list[dict[str, Any]]:
    """Each ``run.log`` call's values, in order."""
    rows = []
    for record in records(path):
        if record.WhichOneof("record_type") == "history":
            items = record.history.item
            rows.append({item.key or "/".join(item.nested_key): json.loads(item.value_json) for item in items})
    return rows


def config(path: Path) -> dict[str, Any]:
    """The run's config (its parameters) as the file holds it."""
    found: dict[str, Any] = {}
    for record in records(path):
        if record.WhichOneof("record_type") == "config":
            for item in record.config.update:
                found[item.key] = json.loads(item.value_json)
        if record.WhichOneof("record_type") == "run":
            for item in record.run.config.update:
                found[item.key] = json.loads(item.value_json)
    return found


def kinds(path: Path) -> set[str]:
    """The kinds of record the file holds (``run``, ``history``, ``artifact``, ``exit``...)."""
    return {record.WhichOneof("record_type") for record in records(path)}
