"""The agent protocol: what the harness calls, in which order, and what it hands over.

An episode runs ``start(context)`` once, then ``act(observation, last)`` until the agent
returns ``Done``/``Failed`` or the step budget is spent, then ``finish(end)``. The agent never
learns the evaluation's verdict: the episode ends before the project is judged, so nothing
an agent remembers can carry the tests into later episodes.
"""

from __future__ import annotations

from typing import ClassVar, Protocol, runtime_checkable

from pydantic import BaseModel, ConfigDict, JsonValue

from workers.agent_api._context import TaskContext
from workers.contract import Action, Mode, Observation


class NoParams(BaseModel):
    """The parameters of an agent that takes none: any given is a config error."""

    model_config = ConfigDict(extra="forbid", frozen=True)


class StepResult(BaseModel):
    """What the environment answered to the agent's previous action."""

    model_config = ConfigDict(frozen=True)

    ok: bool
    error_code: str | None = None
    error_message: str | None = None
    data: JsonValue = None
    """The environment's answer (the composite API's data, or an error's details)."""


class EpisodeEnd(BaseModel):
    """How the episode ended for the agent (never the verdict: the project is judged afterwards)."""

    model_config = ConfigDict(frozen=True)

    stop_reason: str
    """``done``, ``failed``, ``max_steps``, or the error class that ended it (``model_auth``...)."""

    steps: int


@runtime_checkable
class Agent(Protocol):
    """An agent, as the harness drives it. Subclass ``AgentBase`` or write the three methods.

    The class is built with its validated parameters: ``Agent(params)``, ``params`` being an
    instance of its ``Params`` model (``NoParams`` when it declares none).
    """

    Params: ClassVar[type[BaseModel]]
    """The pydantic model of the parameters the sweep config may give (part of the job's identity). An agent
    that calls models besides the job's own gives them in its params and has ``Params`` define
    ``extra_models() -> list[ModelSpec]``, so they get their rate limiters and name the job's model."""

    observes: ClassVar[bool]
    """Whether the environment builds an observation before each action (scripted agents need none)."""

    needs_model: ClassVar[bool]
    """Whether the sweep must give it a model (``context.model()``); checked before anything runs."""

    privileged: ClassVar[bool]
    """Whether it may read the task's solution and the live editor (``context.privileges``): oracles only."""

    modes: ClassVar[tuple[Mode, ...]]
    """The modes it can act in; a sweep asking for another is refused before anything runs."""

    learns: ClassVar[bool]
    """Whether it keeps memory across jobs (see ``LearningAgent``); only such agents take a ``memory`` section."""

    async def start(self, context: TaskContext) -> None:
        """Called once before the first action, with the task and the means to call models."""
        ...

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        """The next action; ``last`` is what the previous one did (None before the first)."""
        ...

    async def finish(self, end: EpisodeEnd) -> None:
        """Called once when the agent's part of the episode is over, however it ended."""
        ...


class AgentBase:
    """Defaults for the protocol: no parameters, observes, no model, not privileged; keeps the context."""

    kinds: ClassVar[tuple[str, ...]] = ("tasks",)
    """The benchmarks it serves: episodes (an agent without the attribute serves them too)."""

    Params: ClassVar[type[BaseModel]] = NoParams
    observes: ClassVar[bool] = True
    needs_model: ClassVar[bool] = False
    privileged: ClassVar[bool] = False
    modes: ClassVar[tuple[Mode, ...]] = ("composite", "primitive")
    learns: ClassVar[bool] = False
    acts_live: ClassVar[bool] = False
    """Whether its actions have happened in the editor when ``act`` returns them (a person's gestures, relayed as
    they are made): the harness records them without performing them again, and gives it the live editor (never
    the solution) in ``context.privileges``."""

    real_time: ClassVar[bool] = False
    """Whether it acts on the wall clock (a person): its jobs' pages run on the real episode clock."""

    exclusive: ClassVar[bool] = False
    """Whether one of its jobs takes the whole local node (a person at the screen): they run one at a time, on
    the machine that runs the sweep."""

    def __init__(self, params: BaseModel | None = None) -> None:
        self.params = params if params is not None else self.Params()
        self.context: TaskContext | None = None

    async def start(self, context: TaskContext) -> None:
        self.context = context

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        raise NotImplementedError

    async def finish(self, end: EpisodeEnd) -> None:
        return None
