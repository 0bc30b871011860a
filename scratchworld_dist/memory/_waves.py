"""Which memory stream a job belongs to, and in which wave it runs.

A stream is one (model, mode, seed) of the sweep: seeds are replicates, so each keeps its own
memory. Its tasks enter waves in the suite's order or a seeded shuffle; both depend only on
the config, so a resumed run rebuilds exactly the same waves.
"""

from __future__ import annotations

import hashlib
import random
import re

from workers.contract import MemorySettings, Mode


def store_name(model_name: str, mode: Mode, seed: int) -> str:
    """A folder-safe name of the stream, unique per model name (the slug alone could collide)."""
    slug = re.sub(r"[^A-Za-z0-9._-]+", "_", model_name).strip("._") or "model"
    tag = hashlib.sha256(model_name.encode()).hexdigest()[:6]
    return f"{slug[:60]}-{tag}.{mode}.seed{seed}"


def task_waves(task_ids: list[str], settings: MemorySettings) -> dict[str, int]:
    """Each task's wave: ``wave_size`` tasks per wave in the configured order (offline: all in wave 0)."""
    order = list(task_ids)
    if settings.order == "shuffled":
        random.Random(settings.seed).shuffle(order)
    if settings.kind == "offline":
        return dict.fromkeys(order, 0)
    return {task: index // settings.wave_size for index, task in enumerate(order)}


def induction_seed(settings: MemorySettings, store: str, wave: int) -> int:
    """The seed of one induction: fixed by the sweep's memory seed, the stream and the wave."""
    digest = hashlib.sha256(f"{settings.seed}:{store}:{wave}".encode()).digest()
    return int.from_bytes(digest[:8], "big")
