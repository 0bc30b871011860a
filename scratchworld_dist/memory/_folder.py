"""A memory store on disk, inside the run directory: ``memory/<store>/``.

``store.json`` says whose stream it is, ``items/<job id>.json`` holds what the job's latest
attempt proposed (with the verdict beside it, read only by the labelled ablation), and
``wave-NNNN.json`` each induced snapshot with the induction's calls and cost. A snapshot once
written is final for the run: resume reads it instead of inducing again.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import TypeVar

from pydantic import BaseModel, ConfigDict, Field, JsonValue, ValidationError

from scratchworld_dist._errors import RunDirError
from scratchworld_dist._files import read_text, write_atomic
from workers.contract import LearnFrom, MemoryItem, MemorySnapshot, Mode, Outcome

MEMORY_DIR = "memory"

_M = TypeVar("_M", bound=BaseModel)


class StoreInfo(BaseModel):
    """Whose stream a store holds."""

    model_config = ConfigDict(frozen=True)

    model: str
    mode: Mode
    seed: int


class JobItems(BaseModel):
    """What one job's latest attempt proposed to learn from."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    wave: int
    outcome: Outcome
    """The verdict, for the ``verdict_ablation`` only; agents never read it."""

    items: list[MemoryItem] = Field(default_factory=list)


class SnapshotRecord(BaseModel):
    """An induced snapshot, with what its induction cost and exchanged."""

    snapshot: MemorySnapshot
    digest: str
    learned_from: list[str] = Field(default_factory=list)
    """Job ids of every item there was to learn from (the induction may have sampled fewer)."""

    llm_calls: int = 0
    input_tokens: int = 0
    output_tokens: int = 0
    cost_usd: float = 0.0
    prompt: list[JsonValue] = Field(default_factory=list)
    reply: str | None = None


class MemoryFolder:
    """One store's files."""

    def __init__(self, run_dir: Path, store: str) -> None:
        self.path = run_dir / MEMORY_DIR / store
        self.store = store

    def describe(self, info: StoreInfo) -> None:
        self.path.joinpath("items").mkdir(parents=True, exist_ok=True)
        write_atomic(self.path / "store.json", info.model_dump_json().encode())

    def info(self) -> StoreInfo | None:
        return _read(self.path / "store.json", StoreInfo)

    def record(self, entry: JobItems) -> None:
        """Keep a job's proposals (a later attempt's replace an earlier one's)."""
        self.path.joinpath("items").mkdir(parents=True, exist_ok=True)
        write_atomic(self.path / "items" / f"{entry.job_id}.json", entry.model_dump_json().encode())

    def entries(self) -> list[JobItems]:
        """Every job's proposals, in a stable order (wave, then job id)."""
        folder = self.path / "items"
        found = [_read(path, JobItems) for path in sorted(folder.glob("*.json"))] if folder.is_dir() else []
        return sorted((e for e in found if e is not None), key=lambda e: (e.wave, e.job_id))

    def snapshot(self, wave: int) -> SnapshotRecord | None:
        return _read(self._snapshot_path(wave), SnapshotRecord)

    def save(self, record: SnapshotRecord) -> None:
        write_atomic(self._snapshot_path(record.snapshot.wave), record.model_dump_json(indent=1).encode())

    def _snapshot_path(self, wave: int) -> Path:
        return self.path / f"wave-{wave:04d}.json"


def learnable(entries: list[JobItems], learn_from: LearnFrom) -> list[MemoryItem]:
    """The items worth learning from: those the agent judged successes (or, in the labelled ablation, every
    item of a job the evaluation passed)."""
    if learn_from == "verdict_ablation":
        return [item for entry in entries if entry.outcome == "passed" for item in entry.items]
    return [item for entry in entries for item in entry.items if item.judged_success]


def offline_source(run_dir: Path, model: str, mode: Mode) -> list[JobItems]:
    """The proposals a previous run's streams of ``model`` in ``mode`` recorded (all its seeds)."""
    root = run_dir / MEMORY_DIR
    if not root.is_dir():
        raise RunDirError(f"{run_dir}: no memory to learn from (it has no {MEMORY_DIR}/ folder: not a learning run)")
    entries: list[JobItems] = []
    for folder in sorted(path for path in root.iterdir() if path.is_dir()):
        store = MemoryFolder(run_dir, folder.name)
        info = store.info()
        if info is not None and info.model == model and info.mode == mode:
            entries.extend(store.entries())
    return sorted(entries, key=lambda e: (e.wave, e.job_id))


def source_digest(entries: list[JobItems]) -> str:
    digest = hashlib.sha256()
    for entry in entries:
        digest.update(entry.model_dump_json().encode())
    return digest.hexdigest()[:16]


def _read(path: Path, model: type[_M]) -> _M | None:
    if not path.is_file():
        return None
    try:
        return model.model_validate_json(read_text(path))
    except (OSError, ValueError, ValidationError) as exc:
        raise RunDirError(f"{path}: unreadable memory file: {' '.join(str(exc).split())[:300]}") from exc
