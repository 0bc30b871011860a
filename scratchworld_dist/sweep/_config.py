"""The sweep config: a YAML file that says which jobs to run, where, and within which limits.

Every field is validated by pydantic and every problem is reported with its path in the file,
so a typo fails before a single browser starts. Relative paths resolve against the config
file's folder, so a config means the same thing from any working directory. What only one kind reads is
in that kind's section (``episodes:``, ``drag:``...); keys that moved there still read at the top level
(``scratchworld_dist.sweep._former_keys``).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Literal, TypeVar

import yaml
from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    ModelWrapValidatorHandler,
    SerializeAsAny,
    SerializerFunctionWrapHandler,
    ValidationError,
    ValidationInfo,
    field_validator,
    model_serializer,
    model_validator,
)
from pydantic_core import ErrorDetails

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._files import read_text
from scratchworld_dist.kinds import DEFAULT_KIND, KindTraits, job_kind, job_kinds
from scratchworld_dist.sweep._former_keys import Notice, into_sections, stderr_notice
from scratchworld_dist.sweep._key_hints import unknown_key_message
from scratchworld_dist.sweep._loggers import Loggers
from scratchworld_dist.sweep._model_config import ModelConfig
from scratchworld_dist.sweep._overrides import SweepOverrides
from scratchworld_dist.sweep._storage import StorageSettings, checked_output
from workers.agent_api import agent_class, checked_agent
from workers.contract import (
    AgentRef,
    AgentUnavailableError,
    EvaluationClock,
    EvaluationPage,
    EvaluationProfile,
    EvaluationRender,
    EvaluationTiming,
    LLMSettings,
    ModelCacheSettings,
    ModelSpec,
    ObservationSettings,
    ProjectLimits,
    RecordSettings,
)
from workers.llm import uncacheable

SectionT = TypeVar("SectionT", bound=BaseModel)


class TaskSelection(BaseModel):
    """Which tasks of the suite to run; empty means all."""

    model_config = ConfigDict(extra="forbid")

    categories: list[Literal["create", "debug", "extend", "compute"]] = Field(default_factory=list)
    ids: list[str] = Field(default_factory=list)
    task_list: str | None = None
    """Upstream task list name (e.g. ``all_tasks``, ``15_tasks``)."""

    limit: int | None = Field(default=None, gt=0)
    """Only N of the selected tasks (or items): the first N in the suite's order (``--limit``: a quick try), or a
    random N (``sample: random``)."""

    sample: Literal["first", "random"] = "first"
    """How ``limit`` picks: the first N in suite order, or N drawn at random with ``sample_seed`` (the same N for
    the same seed and selection, kept in suite order)."""

    sample_seed: int = Field(default=0, ge=0)
    """The seed of a random sample (``--sample-seed``)."""

    @model_validator(mode="after")
    def _sample_needs_limit(self) -> TaskSelection:
        if self.sample == "random" and self.limit is None:
            raise ValueError("sample random draws tasks.limit items: give a limit (--limit N)")
        return self


class Limits(BaseModel):
    """How long, how often and how many at once."""

    model_config = ConfigDict(extra="forbid")

    episode_timeout_s: float = Field(default=900.0, gt=0)
    """Wall-clock limit for one episode (agent and evaluation); past it the job is an error."""

    retries: int = Field(default=2, ge=0)
    """Extra attempts for a job that ended in ``error`` within one run (resume retries again)."""

    pages_per_worker: int | None = Field(default=None, ge=1)
    """Episodes one worker (one browser) runs at once, one page each (default: the browser slots
    spread over one worker per core)."""

    browser_slots: int | None = Field(default=None, ge=1)
    """Editors the local node may hold when Ray is started here. Default: its CPU count for agents
    without a model; for agents that wait on one, what this node's CPU and memory allow, from the
    measured cost of a waiting editor, less ``capacity_margin`` (see docs/admission.md)."""

    capacity_margin: float = Field(default=0.25, ge=0, lt=1)
    """Share of the node's CPU and spare memory kept free when browser slots are derived."""

    memory_reserve_mb: int = Field(default=1024, ge=0)
    """A worker takes no new episode while its node has less memory available than this (the kernel's
    MemAvailable), and takes them again once there is: Chromium is never pushed into the OOM killer."""

    max_in_flight: int | None = Field(default=None, ge=1)
    """Cap on jobs submitted at once (default: all worker pages)."""

    budget_usd: float | None = Field(default=None, gt=0)
    """Model spend of the sweep (all runs of its directory) at which no new job is started."""


class RayConfig(BaseModel):
    """Where Ray runs: a private local instance unless an address is given."""

    model_config = ConfigDict(extra="forbid")

    address: str | None = None
    """``auto`` or ``host:port`` of a running cluster; ``RAY_ADDRESS`` also works."""

    connect_timeout_s: float = Field(default=30.0, gt=0)
    """How long joining the cluster at ``address`` may take before the run fails, naming it."""


class SweepConfig(BaseModel):
    """A whole sweep: its kind, suite and selection, who acts with which models, each kind's section, and how
    to run it."""

    model_config = ConfigDict(extra="forbid")

    name: str = Field(min_length=1, pattern=r"^[A-Za-z0-9][A-Za-z0-9._-]*$")
    benchmark: str = DEFAULT_KIND
    """The job kind (``scratchworld_dist.kinds``): ``tasks``, episodes on a task suite; ``drag``, the single-step
    drag benchmark on a drag suite; ``perception``, the visual perception QA benchmark on a perception suite;
    or a plugin's."""

    suite: Path
    tasks: TaskSelection = Field(default_factory=TaskSelection)
    sections: dict[str, SerializeAsAny[BaseModel]] = Field(default_factory=dict)
    """Each installed kind's own section (``KindTraits.config_section``) by kind name, written under its key
    (``episodes:``, ``drag:``, ``perception:``: ``KindTraits.section_key``): read with ``section``; a section left
    out holds its defaults."""

    agent: AgentRef = Field(default_factory=lambda: AgentRef(name="oracle"))
    """Who acts: a registered name (oracle, noop, llm, a plugin's) or ``package.module:Class``,
    optionally as ``{name, params, label}``; the agent is imported and its params validated here."""
    models: list[ModelConfig] = Field(default_factory=list)
    seeds: list[int] = Field(default_factory=lambda: [0], min_length=1)

    primitive: ObservationSettings = Field(default_factory=ObservationSettings)
    """How primitive-mode observations are made (OCR backend and scope)."""
    profile: EvaluationProfile | None = None
    """Evaluation profile (native | upstream); default: the suite's (upstream clones: upstream)."""
    clock: EvaluationClock | None = None
    """Evaluation clock (virtual | real); default: the suite's (virtual, for ours and upstream clones alike)."""

    render: EvaluationRender | None = None
    """When evaluations draw the stage (on_demand | every_frame); default: on demand."""

    evaluation_page: EvaluationPage | None = None
    """The page evaluations run in (bare | editor); default: bare, the editor for a script that needs it
    (part of each job's identity)."""

    timing: EvaluationTiming | None = None
    """How virtual-clock frames are timed (ideal | calibrated); default: calibrated for upstream in virtual
    time, ideal otherwise (part of each job's identity)."""

    llm: LLMSettings = Field(default_factory=LLMSettings)
    """The llm agent's conversation protocol and model-call retries."""

    project_limits: ProjectLimits = Field(default_factory=ProjectLimits)
    """The largest project a worker loads (task projects are checked when the sweep is planned)."""

    limits: Limits = Field(default_factory=Limits)
    output: Path | str | None = None
    """The run directory (default: ``results/<name>`` in the working directory), or a URL of one on object
    storage (``s3://bucket/prefix``; written through a local mirror, see ``storage``)."""

    storage: StorageSettings = Field(default_factory=StorageSettings)
    """For an ``output`` URL: the local mirror's folder, the lease's term, the wait for uploads at the end."""

    ray: RayConfig = Field(default_factory=RayConfig)
    model_cache: ModelCacheSettings | None = None
    """Opt-in: answer a model request made before from ``model_cache.dir`` (no request, no cost)."""

    loggers: Loggers = Field(default_factory=Loggers)
    """Experiment trackers the run reports to (MLflow, W&B; ``scratchworld_dist.trackers``): none by default."""
    record: RecordSettings = Field(default_factory=RecordSettings)
    """What is recorded of each episode besides its steps: ``{video: true, fps: 5}`` records the agent's editor as
    an MP4 artifact. It changes no job (not part of any id), so a run may turn it on or off when it resumes."""

    tags: dict[str, str] = Field(default_factory=dict)
    """Labels of the run (``--tag key=value``: a team, a ticket, a model revision): recorded in the manifest and
    carried to reports and exports; they change no job, so a run may gain tags when it resumes."""

    @field_validator("output", mode="before")
    @classmethod
    def _output_url_or_path(cls, value: Any) -> Any:
        return checked_output(value)

    @field_validator("tags", mode="before")
    @classmethod
    def _tags_as_text(cls, value: Any) -> Any:
        if isinstance(value, dict):
            return {str(k): "" if v is None else str(v) for k, v in value.items()}
        return value

    probe: bool | None = None
    """Before any job starts, call each model the jobs call once (one short message, ``max_tokens`` 1); default:
    when a model names ``api_key_env``. Keys and base URLs are checked either way (not part of job identity)."""

    @model_validator(mode="wrap")
    @classmethod
    def _kind_sections(cls, data: Any, handler: ModelWrapValidatorHandler[SweepConfig]) -> SweepConfig:
        """Each kind's section validated by its own model, its problems named by their path (``drag.settings.0``);
        keys that moved into a section are read at the top level too (a stored config of older code)."""
        if not isinstance(data, dict):
            return handler(data)
        if "sections" in data:
            raise ValueError("sections is not a field: write each benchmark's section under its key (drag: ...)")
        data, _ = into_sections(data)  # said by sweep_config_from for a file; a stored config is read silently
        sections, problems = {}, []
        for kind in job_kinds():
            if kind.config_section is None:
                continue
            key = kind.section_key()
            try:
                sections[kind.name] = kind.config_section.model_validate(data.pop(key, None) or {})
            except ValidationError as exc:
                problems += [{**e, "loc": (key, *e["loc"])} for e in exc.errors()]  # type: ignore[typeddict-item]
        if not problems:
            return handler({**data, "sections": sections})
        try:
            handler({**data, "sections": sections})
        except ValidationError as exc:
            problems += exc.errors()  # type: ignore[arg-type]
        raise ValidationError.from_exception_data(cls.__name__, problems)  # type: ignore[arg-type]

    @model_serializer(mode="wrap")
    def _sections_by_name(self, handler: SerializerFunctionWrapHandler) -> dict[str, Any]:
        """Sections written back under their keys, as the config file has them."""
        data = handler(self)
        sections = {job_kind(kind).section_key(): value for kind, value in data.get("sections", {}).items()}
        return {**{k: v for k, v in data.items() if k != "sections"}, **sections}

    def section(self, kind: str, model: type[SectionT]) -> SectionT:
        """Kind ``kind``'s section of this config, as ``model`` (its defaults when the file has none)."""
        section = self.sections.get(kind) or model()
        if not isinstance(section, model):
            raise TypeError(f"the {kind} section is a {type(section).__name__}, not a {model.__name__}")
        return section

    @field_validator("seeds", mode="before")
    @classmethod
    def _seed_count(cls, value: Any) -> Any:
        if isinstance(value, int) and not isinstance(value, bool):
            if value < 1:
                raise ValueError("a seed count must be at least 1")
            return list(range(value))
        return value

    @field_validator("seeds")
    @classmethod
    def _distinct_seeds(cls, value: list[int]) -> list[int]:
        if len(set(value)) != len(value):
            raise ValueError("seeds must be distinct")
        return value

    @field_validator("benchmark")
    @classmethod
    def _installed_kind(cls, benchmark: str) -> str:
        job_kind(benchmark)  # UnknownKindError is a ValueError naming the installed kinds
        return benchmark

    @field_validator("agent")
    @classmethod
    def _agent_available(cls, agent: AgentRef, info: ValidationInfo) -> AgentRef:
        if "benchmark" not in info.data:
            return agent  # the benchmark is invalid itself: that error is reported instead
        try:
            job_kind(info.data["benchmark"], KindConfig).check_agent(agent)
        except AgentUnavailableError as exc:
            raise ValueError(str(exc)) from None
        return agent

    @model_validator(mode="after")
    def _video_of_episodes(self) -> SweepConfig:
        if self.record.video and not job_kind(self.benchmark).episodes:
            raise ValueError(f"record.video records agent episodes; the {self.benchmark} benchmark has none")
        return self

    @model_validator(mode="after")
    def _agent_fits_sweep(self) -> SweepConfig:
        job_kind(self.benchmark, KindConfig).check_sweep(self)
        return self

    @model_validator(mode="after")
    def _models_fit_agent(self) -> SweepConfig:
        if job_kind(self.benchmark, KindConfig).needs_model(self) and not self.models:
            raise ValueError("an agent that needs a model needs at least one entry under models")
        settings = [m.spec().identity() for m in self.models]
        if any(settings.count(s) > 1 for s in settings):
            raise ValueError("two models have identical settings; their jobs would be the same jobs")
        names = [m.name or m.model for m in self.models]
        duplicated = sorted({n for n in names if names.count(n) > 1})
        if duplicated:
            raise ValueError(f"model names must be distinct; give these a name: {', '.join(duplicated)}")
        return self

    @field_validator("model_cache")
    @classmethod
    def _cache_replays_answers(
        cls, cache: ModelCacheSettings | None, info: ValidationInfo
    ) -> ModelCacheSettings | None:
        """A model sampled without a seed may not be cached: one sample would stand in for all (asking LiteLLM
        which models take a seed imports it, a few seconds, only for a sweep that caches)."""
        if cache is None or "models" not in info.data or "agent" not in info.data or "benchmark" not in info.data:
            return cache  # the models, the agent or the benchmark are invalid themselves: that error is reported
        helpers = job_kind(info.data["benchmark"], KindConfig).helper_models(info.data["agent"])
        for spec in [*(m.spec() for m in info.data["models"]), *helpers]:
            reason = uncacheable(spec)
            if reason is not None:
                raise ValueError(reason)
        return cache

    def model_specs(self) -> list[ModelSpec | None]:
        """The models of the matrix; a sweep without models (scripted agents) has one model-less column."""
        return [m.spec() for m in self.models] or [None]

    def run_dir(self) -> Path:
        """The local run directory: ``output``, or the local mirror of an ``output`` URL."""
        if isinstance(self.output, str):
            from scratchworld_dist.results.remote._location import parse_location
            from scratchworld_dist.results.remote._mirror import default_mirror

            return default_mirror(parse_location(self.output), self.storage.cache_dir)
        return self.output if self.output is not None else Path("results") / self.name

    def remote_output(self) -> str | None:
        """The URL of a run directory on object storage (None: a local one)."""
        return self.output if isinstance(self.output, str) else None


def load_sweep_config(
    path: str | Path,
    overrides: dict[str, Any] | None = None,
    changes: SweepOverrides | None = None,
    notice: Notice | None = None,
) -> SweepConfig:
    """Read, validate and resolve a sweep config, with the command line's ``changes`` to its fields and
    ``overrides`` of whole fields; raises ``ConfigError`` listing every problem. ``notice`` hears where each
    key given in a former place lives now (default: standard error)."""
    path = Path(path)
    try:
        text = read_text(path)
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"cannot read the config: {exc}", path) from exc
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise ConfigError(f"not valid YAML: {_yaml_problem(exc)}", path) from exc
    if not isinstance(data, dict):
        raise ConfigError("the config must be a mapping of fields (name, suite, agent, ...)", path)
    return sweep_config_from(data, path.parent, overrides, changes, where=path, notice=notice)


def sweep_config_from(
    data: dict[str, Any],
    base: Path,
    overrides: dict[str, Any] | None = None,
    changes: SweepOverrides | None = None,
    *,
    where: Path | None = None,
    notice: Notice | None = None,
) -> SweepConfig:
    """A config's fields (a file's mapping, or one a command builds) validated and resolved, relative paths
    against ``base``; ``ConfigError`` names ``where`` the fields came from. Keys in a former place are moved
    where they are now, ``notice`` (default: standard error) hearing of each once."""
    said: list[str] = []
    try:
        data, said = into_sections(data)  # before the changes, which name a moved key where it is now
    except ValueError as exc:
        raise ConfigError(str(exc), where) from None
    data = (changes or SweepOverrides()).apply(data, said.append)
    data.update(overrides or {})
    for line in dict.fromkeys(said):
        (notice or stderr_notice)(line)
    try:
        config = SweepConfig.model_validate(data)
    except ValidationError as exc:
        problems = "; ".join(f"{_field_path(e['loc'])}: {_problem(e)}" for e in exc.errors())
        raise ConfigError(f"invalid config: {problems}", where) from None
    resolved: dict[str, Any] = {"suite": _resolve(base, config.suite)}
    if isinstance(config.output, Path) and "output" not in (overrides or {}):
        resolved["output"] = _resolve(base, config.output)
    if config.storage.cache_dir is not None:
        resolved["storage"] = config.storage.model_copy(update={"cache_dir": _resolve(base, config.storage.cache_dir)})
    task_list = config.tasks.task_list
    if task_list is not None and (base / task_list).is_file():  # a file next to the config, not a list name
        resolved["tasks"] = config.tasks.model_copy(update={"task_list": str((base / task_list).resolve())})
    resolved["sections"] = {kind: _resolved_paths(base, section) for kind, section in config.sections.items()}
    if config.model_cache is not None and "model_cache" not in (overrides or {}):
        resolved["model_cache"] = ModelCacheSettings(dir=_resolve(base, config.model_cache.dir))
    wandb = config.loggers.wandb
    if wandb is not None and wandb.dir is not None:
        loggers = config.loggers.model_copy(
            update={"wandb": wandb.model_copy(update={"dir": _resolve(base, wandb.dir)})}
        )
        resolved["loggers"] = loggers
    if config.ray.address is None and os.environ.get("RAY_ADDRESS"):
        resolved["ray"] = RayConfig(address=os.environ["RAY_ADDRESS"])
    return config.model_copy(update=resolved)


def _resolved_paths(base: Path, section: SectionT) -> SectionT:
    """A kind's section with its paths (fields of ``Path`` values, or lists of them, in it or in a model it holds:
    ``episodes.memory.from_run``) resolved against ``base``."""
    update: dict[str, Any] = {}
    for name in type(section).model_fields:
        value = getattr(section, name)
        if isinstance(value, Path):
            update[name] = _resolve(base, value)
        elif isinstance(value, list) and value and all(isinstance(item, Path) for item in value):
            update[name] = [_resolve(base, item) for item in value]
        elif isinstance(value, BaseModel):
            update[name] = _resolved_paths(base, value)
    return section.model_copy(update=update)


def _yaml_problem(exc: yaml.YAMLError) -> str:
    """The parser's complaint and where, on one line; never the offending line itself (it may hold a secret)."""
    if not isinstance(exc, yaml.MarkedYAMLError):
        return type(exc).__name__
    problem = ", ".join(part for part in (exc.context, exc.problem) if part) or type(exc).__name__
    mark = exc.problem_mark or exc.context_mark
    where = f"line {mark.line + 1}, column {mark.column + 1}: " if mark is not None else ""
    return where + " ".join(problem.split())


def _resolve(base: Path, path: Path) -> Path:
    return path if path.is_absolute() else (base / path).resolve()


def _problem(error: ErrorDetails) -> str:
    """Pydantic's message, but an unknown key's says which known key it is closest to."""
    if error["type"] == "extra_forbidden" and error["loc"]:
        return unknown_key_message(SweepConfig, error["loc"])
    return error["msg"]


def _field_path(loc: tuple[int | str, ...]) -> str:
    return ".".join(str(part) for part in loc) or "(top level)"


class KindConfig(KindTraits):
    """What a sweep config asks of its benchmark's kind while it is validated. The defaults fit a kind whose jobs
    have one agent, found in the kind's own agent group, that may call a model."""

    def check_agent(self, agent: AgentRef) -> None:
        """Raise ``AgentUnavailableError`` naming the problem unless ``agent`` acts in this kind as given."""
        checked_agent(agent, self.name)

    def check_sweep(self, config: SweepConfig) -> None:
        """Raise ``ValueError`` naming the problem unless the sweep's other fields fit this kind."""
        return None

    def needs_model(self, config: SweepConfig) -> bool:
        """Whether any agent of the sweep calls a model (the sweep then needs one)."""
        return bool(getattr(agent_class(config.agent.name, self.name), "needs_model", False))

    def helper_models(self, agent: AgentRef) -> list[ModelSpec]:
        """Models ``agent`` calls besides the sweep's ``models`` (a grounding model...), as its params name them."""
        return []
