"""When the GUI run leaves the plan: the oracle's error, and what differs between two project states."""

from __future__ import annotations

from pydantic import JsonValue, ValidationError

from workers.agents._primitive_oracle._state import ProjectSnapshot, ScriptBlock, ScriptChain
from workers.contract import AgentUnableError, ScratchWorldError


class OracleDivergenceError(AgentUnableError):
    """A gesture did not have the effect the oracle planned, the editor is not in the planned state,
    or the page answered a read in a shape the oracle cannot use. The plan, the editor's layout and its
    answers are the same on every run of the job, so a retry would diverge the same way: not retried."""


class OracleWaitError(ScratchWorldError):
    """A condition the oracle waits for after a gesture did not come in time: it may on another run (a
    busy machine, the real clock), so the job is retried as any crash is."""


def describe_difference(expected: ProjectSnapshot, actual: JsonValue) -> str:
    """What differs between two geometrySnapshot states, in a few readable lines."""
    try:
        have_state = ProjectSnapshot.model_validate(actual)
    except ValidationError:
        return f"no snapshot could be read (got {actual!r})"
    problems: list[str] = []
    if expected.editing_target != have_state.editing_target:
        problems.append(f"editing {have_state.editing_target!r}, expected {expected.editing_target!r}")
    mine = {t.name: t for t in have_state.targets}
    for target in expected.targets:
        name = target.name
        have = mine.get(name)
        if have is None:
            problems.append(f"target {name!r} is missing")
            continue
        if have.variables != target.variables:
            problems.append(f"{name} variables {have.variables}, expected {target.variables}")
        missing = [s for s in target.scripts if s not in have.scripts]
        extra = [s for s in have.scripts if s not in target.scripts]
        for script in missing:
            problems.append(f"{name} lacks script {script_text(ScriptChain.model_validate_json(script).root)}")
        for script in extra:
            problems.append(f"{name} has unexpected script {script_text(ScriptChain.model_validate_json(script).root)}")
    return "; ".join(problems) or "the states differ"


def script_text(chain: list[ScriptBlock]) -> str:
    """A compact one-line rendering of a snapshot script: ``opcode[FIELD=v](INPUT: ...) > next``."""
    parts = []
    for block in chain:
        text = block.opcode
        if block.fields:
            text += "[" + ",".join(f"{k}={v}" for k, v in block.fields.items()) + "]"
        inputs = [f"{k}: {script_text(v)}" for k, v in block.inputs.items()]
        if inputs:
            text += "(" + "; ".join(inputs) + ")"
        parts.append(text)
    return " > ".join(parts)
