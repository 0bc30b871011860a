"""The contract between the driver and a worker: what every job is given and what it returns, whatever its kind.

Every kind's job spec extends ``JobHeader`` (and ``AgentJob`` when an agent acts in it) in the kind's own
folder (``workers/kinds/<kind>/_contract.py``); here is what they all share: the header, the agent reference,
the task payload, the result and its steps. Everything here crosses process (and host) boundaries through Ray,
so it is plain pydantic data: the driver never sends paths a remote node could not open, only the bytes and
sources it needs.
"""

from __future__ import annotations

import re
from typing import Any, Literal

from pydantic import BaseModel, ConfigDict, Field, JsonValue, SerializeAsAny, field_validator, model_validator

from workers.contract._actions import CompositeAction
from workers.contract._errors import ModelErrorClass
from workers.contract._eval_result import EvalResult
from workers.contract._evaluation_spec import EvaluationSpec
from workers.contract._memory import MemoryItem
from workers.contract._model import LLMSettings, ModelCacheSettings, ModelSpec
from workers.contract._observations import StepObservation
from workers.contract._video import EpisodeVideo

Mode = Literal["composite", "primitive"]
Outcome = Literal["passed", "failed", "error"]
ClockMode = Literal["real", "virtual"]
"""Whose time an agent's page runs on (see ``EpisodeClock``)."""

ErrorClass = Literal[
    "episode_timeout",  # the episode ran past its limit and was cancelled
    "worker_died",  # the worker process (or its browser) died while the job was in flight
    "editor_failure",  # the editor could not be opened, loaded or evaluated in
    "evaluator_error",  # the evaluation produced no verdict for reasons outside the project
    "agent_error",  # the agent itself crashed (a bug in it)
    "agent_unable",  # the agent said it cannot go on and would fail the same way again: permanent
    "participant_left",  # a person (the human agent) closed their page before submitting or giving up
    "task_invalid",  # the task's initial project cannot be loaded (over the limits, corrupt): permanent
    "harness_mismatch",  # the worker runs other code than the driver planned the job for
    "internal_error",  # anything else: a bug in this harness
    ModelErrorClass,
]
"""Why a job produced no verdict; kept out of SR/PSR, and retried unless it is permanent."""

PERMANENT_ERRORS: frozenset[str] = frozenset(
    {
        "task_invalid",
        "agent_unable",
        "model_auth",
        "model_bad_request",
        "model_not_found",
        "model_context_window",
        "model_content_policy",
    }
)
"""Error classes the driver does not retry: the same request would fail the same way."""


_AGENT_NAME = re.compile(r"[A-Za-z_][\w.-]*(:[A-Za-z_][\w.]*)?")


class JobDetail(BaseModel):
    """A kind's own result; each kind's detail adds its fields (a plugin kind's too)."""

    model_config = ConfigDict(frozen=True)

    kind: str
    """The job kind that made it (``drag``, ``perception`` or a plugin's)."""


class AgentRef(BaseModel):
    """Which agent acts, with which parameters: a registered name, or ``package.module:Class``.

    Name and parameters are part of a job's identity (the parameters are validated by the
    agent's own model before anything runs); the label only names it in reports.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    name: str = Field(max_length=200)
    """A name registered under the ``scratchworld.agents`` entry points, or ``package.module:Class``."""

    params: dict[str, JsonValue] = Field(default_factory=dict)
    label: str | None = Field(default=None, max_length=200)
    """How reports name the agent (default: its name)."""

    @model_validator(mode="before")
    @classmethod
    def _from_name(cls, value: Any) -> Any:
        return {"name": value} if isinstance(value, str) else value

    @field_validator("name")
    @classmethod
    def _plain(cls, name: str) -> str:
        if not _AGENT_NAME.fullmatch(name):
            raise ValueError(f"{name!r} is neither a registered agent name nor package.module:Class")
        return name

    @property
    def display(self) -> str:
        return self.label or self.name

    def identity(self) -> dict[str, JsonValue]:
        """What can change a job's result: the agent and its parameters (not the label)."""
        return {"name": self.name, "params": self.params}


class EpisodeClock(BaseModel):
    """How time passes on the agent's page.

    ``real``: page time runs on, also while the model thinks, so what an agent sees depends on its
    provider's latency and the machine's load. ``virtual``: page time stands still between actions
    and moves by 50 ms before each, by a drag's duration during it, by ``settle_ms`` (plus ``think_ms``)
    after each, and by ``start_ms`` before the first observation: the same agent and seed see the
    same pages on any machine and with any provider.
    """

    model_config = ConfigDict(frozen=True, extra="forbid")

    mode: ClockMode = "real"
    start_ms: int = Field(default=1000, ge=600, le=60_000)
    """Virtual page time between loading the task's project and the first observation. At least 600:
    the editor drops panel updates (the code area's sprite picture) within 500 ms of the last one,
    so the panels are drawn anew once that much time has passed (see ``Editor.redraw_panels``)."""

    settle_ms: int = Field(default=500, ge=0, le=60_000)
    """Virtual page time after each action (15 of the VM's frames by default)."""

    think_ms: int = Field(default=0, ge=0, le=600_000)
    """Virtual page time added after each action, standing in for a model's thinking time."""

    @model_validator(mode="before")
    @classmethod
    def _mode_alone(cls, data: Any) -> Any:
        return {"mode": data} if isinstance(data, str) else data

    @property
    def step_ms(self) -> int:
        return self.settle_ms + self.think_ms


class JobHeader(BaseModel):
    """What every job a worker is sent has, whatever its kind: which job and attempt, its item, its time limit and
    the harness it was planned under. Each kind's spec extends it with what only that kind uses."""

    model_config = ConfigDict(frozen=True)

    job_id: str
    attempt: int = Field(ge=1)
    task_id: str
    """The task's (or drag task's, or perception item's) id."""

    timeout_s: float = Field(gt=0)
    """Wall-clock limit for the whole job (an episode: agent and evaluation included; a regrade: the evaluation,
    editor included)."""

    harness: str | None = None
    """The harness fingerprint the driver planned the job under; a worker running other code refuses it."""

    trace_parent: str | None = None
    """The W3C ``traceparent`` of the driver's span of this attempt (``workers.tracing``): the worker's spans join
    its trace. Set only while tracing; never part of the job's identity (the id is the plan's, made without it)."""


class AgentJob(JobHeader):
    """The header of a job an agent acts in: who acts, with which model and seed, how its model is called."""

    agent: AgentRef
    agent_code: str | None = None
    """Digest of a plugin agent's code as the driver found it; a worker with other code refuses the job."""

    model: ModelSpec | None
    seed: int
    llm: LLMSettings | None = None
    """The conversation protocol and retry policy of model calls (None means the defaults)."""

    model_cache: ModelCacheSettings | None = None
    """Where successful model replies are stored and replayed from (None: every call goes to the model)."""


WorkerJob = JobHeader
"""Any job a worker runs, as it is sent for one attempt: a kind's spec, found by its class (``workers.kinds``)."""


class TaskPayload(BaseModel):
    """The task's content, shipped once per task to the object store and shared by its jobs."""

    model_config = ConfigDict(frozen=True)

    task_id: str
    category: str
    instruction: str
    initial_project: bytes
    golden_project: bytes | None
    golden_trajectory: list[CompositeAction] | None = None
    """Composite actions that turn the initial project into a solution (replayed by the oracle)."""

    evaluation: EvaluationSpec


class StepRecord(BaseModel):
    """One agent action and what the environment answered."""

    index: int = Field(ge=0)
    action: str
    """The action's name (``done``, ``add_block``, ``click``...)."""

    args: dict[str, JsonValue] = Field(default_factory=dict)
    ok: bool
    """Whether the environment accepted and carried out the action."""

    error_code: str | None = None
    error_message: str | None = None
    data: JsonValue = None
    """What the environment answered (a composite envelope's data or error details)."""

    latency_s: float = 0.0
    """Wall time of the observation, the agent's decision and the action."""

    observation_s: float = 0.0
    """Wall time of the observation alone (0 for agents that do not observe)."""

    warnings: list[str] = Field(default_factory=list)
    """Degradations of this step's observation (e.g. OCR down: a DOM-only element list)."""

    llm_calls: int = 0
    llm_cache_hits: int = 0
    """Of ``llm_calls``, those answered from the model cache (no request, no cost)."""

    input_tokens: int = 0
    output_tokens: int = 0
    cost_usd: float = 0.0
    prompt: list[JsonValue] = Field(default_factory=list)
    """Messages this step added to the model's conversation (the system prompt on the first step);
    images appear as ``{"type": "image_ref", "sha256": ...}`` into ``JobResult.images``."""

    reply: str | None = None
    """The model's raw reply."""

    reasoning: str | None = None
    """The reasoning the provider returned apart from the reply (e.g. a reasoning model's), for the newest call."""

    started_at: float | None = None
    """When the step began (its observation), as seconds since the epoch on the worker's clock."""

    episode_clock_ms: int | None = None
    """The agent page's time when the step began, on the virtual episode clock (None on the real clock)."""

    observation: StepObservation | None = None
    """What the environment showed before the step (None for agents that do not observe)."""


class WorkerInfo(BaseModel):
    """Where a job ran."""

    model_config = ConfigDict(frozen=True)

    node_id: str
    hostname: str
    pid: int
    worker_index: int


class WorkerLoad(BaseModel):
    """What a worker's browser holds and what its node has left, as the worker measured them."""

    model_config = ConfigDict(frozen=True)

    editors: int
    """Editor pages the worker's browser held (in use and idle) when ``browser_pss_bytes`` was read."""

    browser_pss_bytes: int
    """Proportional set size of the worker's browser processes (see ``workers.node.browser_usage``), read at
    most ``USAGE_MAX_AGE_S`` (30 s) before."""

    node_available_bytes: int
    """The node's available memory (the kernel's MemAvailable)."""

    admits: bool
    """Whether the worker takes new episodes: its node has at least the sweep's memory reserve available."""


class Refusal(BaseModel):
    """A job a worker declined without starting it (its node is short of memory): not an attempt."""

    model_config = ConfigDict(frozen=True)

    reason: str
    load: WorkerLoad


class EpisodeTimings(BaseModel):
    """Wall-clock seconds per phase of an episode."""

    setup_s: float = 0.0
    agent_s: float = 0.0
    evaluation_s: float = 0.0
    total_s: float = 0.0


class JobResult(BaseModel):
    """What a worker returns for one job; the driver turns it into result rows."""

    job_id: str
    attempt: int
    outcome: Outcome
    error_class: ErrorClass | None = None
    error_message: str | None = None
    stop_reason: str
    """``done``, ``failed`` (agent gave up), ``max_steps``, or the error class."""

    evaluation: EvalResult | None = None
    steps: list[StepRecord] = Field(default_factory=list)
    final_project: bytes | None = None
    images: dict[str, bytes] = Field(default_factory=dict, repr=False)
    """Images the prompts showed, by SHA-256, each stored once however often it was sent."""

    timings: EpisodeTimings = Field(default_factory=EpisodeTimings)
    video: EpisodeVideo | None = Field(default=None, repr=False)
    """The agent's editor recorded, when the job asked for it (``RecordSettings.video``); an artifact only."""

    memory_items: list[MemoryItem] = Field(default_factory=list)
    """What a learning agent proposed to learn from this episode, each with its own judgement."""

    detail: SerializeAsAny[JobDetail] | None = None
    """What only the job's kind has (a drag's points and distances, a perception answer's scores; None for
    episodes)."""

    worker: WorkerInfo | None = None
    load: WorkerLoad | None = None
    """The worker's browser and node when the episode ended (None when it never reached a worker)."""

    started_at: float = 0.0
    """Unix time the worker started the episode."""

    finished_at: float = 0.0

    @property
    def llm_calls(self) -> int:
        return sum(step.llm_calls for step in self.steps)

    @property
    def llm_cache_hits(self) -> int:
        return sum(step.llm_cache_hits for step in self.steps)

    @property
    def input_tokens(self) -> int:
        return sum(step.input_tokens for step in self.steps)

    @property
    def output_tokens(self) -> int:
        return sum(step.output_tokens for step in self.steps)

    @property
    def cost_usd(self) -> float:
        return sum(step.cost_usd for step in self.steps)

    @classmethod
    def errored(
        cls,
        spec: WorkerJob,
        error_class: ErrorClass,
        message: str,
        *,
        steps: list[StepRecord] | None = None,
    ) -> JobResult:
        """A result with no verdict, for the driver to retry or record."""
        return cls(
            job_id=spec.job_id,
            attempt=spec.attempt,
            outcome="error",
            error_class=error_class,
            error_message=message,
            stop_reason=error_class,
            steps=steps or [],
        )


def outcome_of(evaluation: EvalResult) -> tuple[Outcome, ErrorClass | None]:
    """Map a verdict to the three outcome classes the reports use.

    A project the agent broke, or one that makes the script throw or hang, is the agent's
    failure (upstream scores it 0); an evaluation the editor could not carry out is an error.
    """
    if evaluation.error is None:
        return ("passed" if evaluation.success else "failed"), None
    if evaluation.error.kind == "editor_failure":
        return "error", "editor_failure"
    if evaluation.error.kind in {"script_invalid", "result_invalid"}:
        # The task's own script is broken: no verdict about the agent can be drawn.
        return "error", "evaluator_error"
    return "failed", None
