"""The task episodes' section of a sweep config, ``episodes:``: what only episodes read (their modes and step
limits, the page clock, planned oracle trajectories, memory across jobs, synthetic stand-ins).

The key is ``episodes``, not the kind's name: ``tasks:`` is the task selection every kind reads. These were
top-level fields until the section existed; ``former_keys`` lets a config that still writes them there read as
before (moved here with a notice, ``scratchworld_dist.sweep``), so its jobs keep their ids.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, ClassVar, get_args

from pydantic import BaseModel, ConfigDict, Field, PlainValidator, field_validator, model_validator

from workers.contract import EpisodeClock, MemorySettings, Mode, SyntheticEpisodes

EPISODES_KEY = "episodes"
"""The section's key in a sweep config (``TasksKind.config_key``)."""


def _step_limits(value: Any) -> int | dict[Mode, int]:
    """A positive step limit, or one per mode (``{composite: 50, primitive: 300}``)."""

    def positive(limit: Any, where: str) -> int:
        if isinstance(limit, bool) or not isinstance(limit, int) or limit < 1:
            raise ValueError(f"{where}must be a positive integer, not {limit!r}")
        return limit

    if not isinstance(value, dict):
        return positive(value, "a step limit (or a mapping of mode to step limit) ")
    modes = get_args(Mode)
    unknown = [str(mode) for mode in value if mode not in modes]
    if unknown:
        raise ValueError(f"unknown mode {', '.join(unknown)}; modes: {', '.join(modes)}")
    return {mode: positive(limit, f"the step limit of {mode} ") for mode, limit in value.items()}


class EpisodeSweep(BaseModel):
    """The task episodes' own settings (``benchmark: tasks``): jobs are model x mode x task x seed."""

    model_config = ConfigDict(extra="forbid")

    former_keys: ClassVar[tuple[str, ...]] = (
        "modes",
        "max_steps",
        "oracle_trajectories",
        "episode_clock",
        "memory",
        "synthetic",
    )
    """Top-level keys of older configs that are fields of this section now (all of them)."""

    resume_free: ClassVar[dict[str, Any]] = {"memory": {"from_run"}}
    """What may change between sessions of one run: offline memory's source folder may move."""

    modes: list[Mode] = Field(default_factory=lambda: ["composite"], min_length=1)
    max_steps: Annotated[int | dict[Mode, int], PlainValidator(_step_limits)] = 50
    """Step limit per episode; a mapping gives each mode its own (a GUI gesture does less than an API call)."""

    oracle_trajectories: Path | None = None
    """A folder of ``<task id>.json`` trajectories (``scratchworld oracle-plan``'s output) for tasks that
    ship none: the oracle replays them (composite) or acts them out (primitive) instead of loading the golden."""

    episode_clock: EpisodeClock | None = None
    """How time passes on the agent's page (``virtual`` or ``{mode, start_ms, settle_ms, think_ms}``);
    default: virtual, for our suites and upstream clones alike (``real`` is upstream's own protocol)."""

    memory: MemorySettings | None = None
    """Memory shared across jobs, for agents that learn (``awm``): online waves, or offline from a run dir."""

    synthetic: SyntheticEpisodes | None = None
    """Run browserless synthetic episodes instead, for all tasks or those in ``synthetic.tasks`` (benchmarks)."""

    @field_validator("modes")
    @classmethod
    def _distinct_modes(cls, value: list[Mode]) -> list[Mode]:
        if len(set(value)) != len(value):
            raise ValueError("modes must be distinct")
        return value

    @model_validator(mode="after")
    def _steps_for_every_mode(self) -> EpisodeSweep:
        if isinstance(self.max_steps, dict):
            missing = [mode for mode in self.modes if mode not in self.max_steps]
            if missing:
                raise ValueError(f"max_steps has no limit for mode {', '.join(missing)}")
        return self
