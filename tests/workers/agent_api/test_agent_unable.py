"""An agent that says it cannot go on (``AgentUnableError``, as the primitive oracle does when a plan cannot be
acted out) ends its job as ``agent_unable``, which the driver does not retry: the same job would end the same
way. A crash (any other exception) stays ``agent_error`` and is retried."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
import yaml

from scratchworld_dist.results import RunStore
from tests.conftest import SUITE_DIR
from tests.support.sweep_driver import run_here
from workers.agent_api import Action, AgentBase, AgentUnableError, Observation, StepResult


class GivesUp(AgentBase):
    """Cannot act out its plan, whatever happens around it."""

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        raise AgentUnableError("no clean drag path into the operator's input")


class Crashes(AgentBase):
    """A bug: fails in a way a retry may not repeat."""

    async def act(self, observation: Observation | None, last: StepResult | None) -> Action:
        raise RuntimeError("flaky")


def config(tmp_path: Path, agent: str) -> Path:
    path = tmp_path / f"{agent}.yaml"
    fields: dict[str, Any] = {
        "name": agent, "suite": str(SUITE_DIR), "agent": f"{__name__}:{agent}",
        "tasks": {"ids": ["sum_two_numbers"]}, "limits": {"retries": 2}, "output": str(tmp_path / agent),
    }  # fmt: skip
    path.write_text(yaml.safe_dump(fields))
    return path


@pytest.mark.ray
@pytest.mark.browser
def test_an_unable_agent_is_recorded_once_and_a_crash_is_retried(tmp_path: Path, shared_ray: int) -> None:
    code, out = run_here(config(tmp_path, "GivesUp"))
    assert code == 1, out  # an error is left: the run says so
    (row,) = RunStore(tmp_path / "GivesUp").job_rows()
    assert (row.outcome, row.error_class, row.attempt) == ("error", "agent_unable", 1)  # not retried
    assert "no clean drag path" in (row.error_message or "") and row.stop_reason == "agent_unable"
    code, out = run_here(config(tmp_path, "Crashes"))
    rows = RunStore(tmp_path / "Crashes").job_rows()
    assert code == 1 and sorted((r.error_class, r.attempt) for r in rows) == [("agent_error", n) for n in (1, 2, 3)]
