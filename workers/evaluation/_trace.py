"""The observable trace of an evaluation: what a user could see and hear, frame by frame.

A mutant that passes every test is either equivalent to the golden or a hole in the grader; running
both under the same inputs (the script's mouse, keys and answers, and the same ``Math.random`` seed)
and comparing what they show tells the two apart by behaviour (``first_difference``). The page
records it (``scratch-gui/trace/record.js``) after each VM frame while the script runs, keeping only
the fields that changed; this module is its Python shape.
"""

from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, JsonValue
from pydantic.alias_generators import to_camel

from workers.contract import EvalResult

DEFAULT_TRACE_CHARS = 2_000_000
"""Cap on a trace's JSON (the sum of its frames'): our suite's goldens record well under 100 kB."""

MIN_TRACE_CHARS = 1000
MAX_TRACE_CHARS = 16 * 1024 * 1024
"""The page's limits on the cap (a trace crosses the browser protocol in one piece)."""

STAGE = "Stage"
"""The stage's key among the targets; sprites are keyed by name, clones as ``<sprite>#<n>`` in creation order."""

EVENT_FIELDS = frozenset({"sounds"})
"""Fields that say what happened in their frame only (sound names started), not a state that lasts."""

VARIABLE_PREFIX = "var:"
"""Variables and lists are the fields ``var:<id>``, valued ``[name, value, monitor shown]`` (a list's value
is its items); values are strings as Scratch shows them."""


class TraceFrame(BaseModel):
    """What changed in one VM frame: the fields per target key (a new target: all of them), targets gone."""

    model_config = ConfigDict(frozen=True)

    frame: int = Field(ge=0)
    """VM steps since the script started (0: its start, when every field of every target is recorded)."""

    targets: dict[str, dict[str, JsonValue]] = Field(default_factory=dict)
    removed: list[str] = Field(default_factory=list)
    """Keys of targets that no longer exist (deleted clones)."""


class ObservableTrace(BaseModel):
    """The frames of one evaluation in which something a user could observe changed."""

    model_config = ConfigDict(frozen=True, alias_generator=to_camel, populate_by_name=True)

    frames: list[TraceFrame]
    steps: int = Field(ge=0)
    """VM frames (steps) the script's run took."""

    truncated_at: int | None = None
    """The first frame left out once the trace reached its size cap; None: the trace is whole."""

    chars: int = Field(ge=0)
    """Size of the recorded frames as JSON."""

    @property
    def truncated(self) -> bool:
        return self.truncated_at is not None


class TracedEvaluation(BaseModel):
    """A verdict and the observable trace of the run that gave it (None when there was no run to record:
    a project refused or that failed to load, a page killed for blocking)."""

    result: EvalResult
    trace: ObservableTrace | None
    record_s: float | None = None
    """Real seconds the page spent recording (taking snapshots), a part of the script phase's time."""
