"""The ``tasks`` kind's jobs as a worker is sent them: an episode, and a regrade of the project one left.

An episode's agent acts in the task's initial project until it stops; then the project is judged. A regrade
runs no agent: the worker loads ``project`` into one of its clean evaluation editors and runs the evaluation
spec of the task payload it is sent with (which names the profile and the clock).
"""

from __future__ import annotations

from pydantic import Field

from workers.contract import (
    MAX_SEED,
    AgentJob,
    EpisodeClock,
    JobHeader,
    MemorySnapshot,
    Mode,
    ObservationSettings,
    ProjectLimits,
    RecordSettings,
)


class EpisodeSpec(AgentJob):
    """One episode as a worker sees it: who acts, in which mode, for how long."""

    mode: Mode
    max_steps: int = Field(gt=0)
    observation: ObservationSettings | None = None
    """How primitive observations are made (primitive mode; None means the defaults)."""

    project_limits: ProjectLimits = Field(default_factory=ProjectLimits)
    """The largest project the worker loads (initial, loaded by the agent, evaluated)."""

    memory: MemorySnapshot | None = None
    """What a learning agent is shown of its memory in this episode (None: the sweep keeps no memory)."""

    episode_clock: EpisodeClock = Field(default_factory=EpisodeClock)
    """How time passes on the agent's page."""

    record: RecordSettings = Field(default_factory=RecordSettings)
    """What is recorded of the episode besides its steps (a video); not part of the job's identity."""


class RegradeSpec(JobHeader):
    """One regrade as a worker sees it: which stored project to evaluate against which task."""

    project: bytes = Field(repr=False)
    """The final project the source attempt stored (``final.sb3``)."""

    evaluation_seed: int = Field(ge=0, le=MAX_SEED)
    """The ``Math.random`` seed the source episode was judged under (``workers.contract.evaluation_seed``)."""

    project_limits: ProjectLimits = Field(default_factory=ProjectLimits)
