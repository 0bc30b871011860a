"""The memory service: keeps every stream's store and induces its snapshots, wave by wave.

It runs as one Ray actor on the driver's node (``start_memory_service``), so the driver's run
directory is local to it; workers never write memory, the driver hands it each job's proposals
before committing the job's rows. Inductions call the stream's model through the harness's
client (retries, rate limits, cost), and each snapshot records what its induction cost.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from scratchworld_dist.memory._folder import JobItems, MemoryFolder, SnapshotRecord, StoreInfo, learnable
from scratchworld_dist.memory._waves import induction_seed
from workers.agent_api import InductionRequest, agent_class, agent_params
from workers.contract import AgentRef, MemoryItem, MemorySettings, MemorySnapshot, Mode, ModelSpec, RetryPolicy

SEED_RANGE = 2**31
"""Model-call seeds stay within what providers accept."""


class MemoryKeeper:
    """All stores of one run directory (use through ``start_memory_service`` in a sweep)."""

    def __init__(
        self,
        run_dir: str,
        agent: AgentRef,
        settings: MemorySettings,
        policy: RetryPolicy,
        sources: dict[tuple[str, Mode], list[JobItems]] | None = None,
    ) -> None:
        """``sources``: offline memory's items per (model name, mode), read from the previous run."""
        self.run_dir = Path(run_dir)
        self.agent = agent
        self.settings = settings
        self.policy = policy
        self.sources = sources or {}

    async def record(self, store: str, info: StoreInfo, entry: JobItems) -> None:
        folder = MemoryFolder(self.run_dir, store)
        if folder.info() is None:
            folder.describe(info)
        folder.record(entry)

    async def snapshot(self, store: str, wave: int, mode: Mode, model: ModelSpec | None) -> MemorySnapshot:
        """The memory wave ``wave`` of ``store`` reads: the persisted one, else induced now (and persisted)."""
        folder = MemoryFolder(self.run_dir, store)
        found = folder.snapshot(wave)
        if found is not None:
            return found.snapshot
        if folder.info() is None and model is not None:
            folder.describe(StoreInfo(model=model.name, mode=mode, seed=_seed_of(store)))
        if self.settings.kind == "offline":
            entries = self.sources.get((model.name if model is not None else "", mode), [])
        else:
            entries = [entry for entry in folder.entries() if entry.wave < wave]
        items = learnable(entries, self.settings.learn_from)
        record = await self._next(folder, wave, mode, model, items)
        folder.save(record)
        return record.snapshot

    async def _next(
        self, folder: MemoryFolder, wave: int, mode: Mode, model: ModelSpec | None, items: list[MemoryItem]
    ) -> SnapshotRecord:
        learned_from = [item.source for item in items]
        if not items or model is None:
            return _record(MemorySnapshot(store=folder.store, wave=wave), learned_from)
        previous = folder.snapshot(wave - 1) if wave > 0 else None
        if previous is not None and previous.learned_from == learned_from:  # nothing new to learn from
            carried = previous.snapshot.model_copy(update={"wave": wave})
            return _record(carried, learned_from)
        return await self._induce(folder.store, wave, mode, model, items, learned_from)

    async def _induce(
        self, store: str, wave: int, mode: Mode, model: ModelSpec, items: list[MemoryItem], learned_from: list[str]
    ) -> SnapshotRecord:
        from workers.agents import EpisodeModels  # the model client: loaded only where inductions run

        cls: Any = agent_class(self.agent.name)
        params = agent_params(cls, self.agent)
        seed = induction_seed(self.settings, store, wave)
        models = EpisodeModels(self.policy, seed % SEED_RANGE)
        request = InductionRequest(mode=mode, store=store, wave=wave, items=items, seed=seed)
        update = await cls.induce(params, request, models.connect(model))
        calls = models.drain()
        snapshot = MemorySnapshot(store=store, wave=wave, text=update.text, sources=update.sources)
        return SnapshotRecord(
            snapshot=snapshot,
            digest=snapshot.digest,
            learned_from=learned_from,
            llm_calls=calls.llm_calls,
            input_tokens=calls.input_tokens,
            output_tokens=calls.output_tokens,
            cost_usd=calls.cost_usd,
            prompt=calls.prompt,
            reply=calls.reply,
        )


def _record(snapshot: MemorySnapshot, learned_from: list[str]) -> SnapshotRecord:
    return SnapshotRecord(snapshot=snapshot, digest=snapshot.digest, learned_from=learned_from)


def _seed_of(store: str) -> int:
    return int(store.rsplit(".seed", 1)[1])


def start_memory_service(
    run_dir: Path,
    agent: AgentRef,
    settings: MemorySettings,
    policy: RetryPolicy,
    sources: dict[tuple[str, Mode], list[JobItems]] | None = None,
) -> Any:
    """The keeper as a Ray actor pinned to this (the driver's) node; call its methods with ``.remote``."""
    import ray
    from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

    here = NodeAffinitySchedulingStrategy(node_id=ray.get_runtime_context().get_node_id(), soft=False)
    actor = ray.remote(num_cpus=0)(MemoryKeeper)
    return actor.options(scheduling_strategy=here).remote(str(run_dir), agent, settings, policy, sources)
