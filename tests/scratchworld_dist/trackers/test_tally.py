"""The metrics a run reports to its trackers, from its events: per mode and per mode and category, a job counted by
its last attempt, cost by every attempt; and the ``loggers:`` section of the config."""

from __future__ import annotations

from pathlib import Path

import pytest

from scratchworld_dist._errors import ConfigError
from scratchworld_dist._sweep_manifest import config_hash
from scratchworld_dist.results import JobError, JobRetry, JobStart
from scratchworld_dist.sweep import sweep_config_from
from scratchworld_dist.trackers import TRACKERS, PlannedJob, RunTally, configured_trackers, redacted
from tests.conftest import REPO
from tests.support.run_events import finish, job_fields


def test_metrics_follow_each_jobs_last_attempt() -> None:
    planned = {
        "a": PlannedJob("m", "composite", "create"),
        "b": PlannedJob("m", "composite", "create"),
        "c": PlannedJob("m", "composite", "debug"),
        "d": PlannedJob("m", "primitive", "debug"),
    }
    tally = RunTally(planned)
    assert tally.metrics()["composite/coverage"] == 0.0
    assert "composite/sr" not in tally.metrics()  # no verdict yet: no rate to report
    assert not tally.hear(JobStart(**job_fields("a"), worker=0))
    assert tally.hear(JobRetry(**job_fields("a"), error_class="episode_timeout", message="x", cost_usd=0.25))
    assert tally.hear(finish("a", "passed", 3, 3, cost=0.5, attempt=2))
    assert tally.hear(finish("b", "failed", 1, 4))
    assert tally.hear(JobError(**job_fields("c"), error_class="episode_timeout", message="x", cost_usd=0.0))
    assert not tally.hear(finish("other", "passed", 1, 1))  # a job of another plan
    metrics = tally.metrics()
    assert metrics["composite/sr"] == 0.5
    assert metrics["composite/psr"] == pytest.approx((1.0 + 0.25) / 2)
    assert metrics["composite/coverage"] == pytest.approx(2 / 3)
    assert metrics["composite/cost_usd"] == pytest.approx(0.75)
    assert metrics["composite/create/sr"] == 0.5
    assert metrics["composite/debug/coverage"] == 0.0
    assert metrics["primitive/coverage"] == 0.0
    assert metrics["decided"] == 2.0
    tally.hear(finish("c", "passed", 2, 2))  # an error decided by a later session
    assert tally.metrics()["composite/debug/sr"] == 1.0
    assert tally.metrics()["decided"] == 3.0


def test_several_models_are_told_apart() -> None:
    tally = RunTally({"a": PlannedJob("m1", "composite", "create"), "b": PlannedJob("m2", "composite", "create")})
    tally.hear(finish("a", "passed", 1, 1))
    assert tally.metrics()["m1/composite/sr"] == 1.0
    assert "m2/composite/sr" not in tally.metrics()


def test_credentials_in_a_url_are_left_out() -> None:
    assert (
        redacted("cannot reach https://alice:s3cret@mlflow.lab:5000/api")
        == "cannot reach https://***@mlflow.lab:5000/api"
    )


def _config(tmp_path: Path, loggers: object) -> dict[str, object]:
    return {"name": "t", "suite": str(REPO / "tasks"), "agent": "oracle", "loggers": loggers}


def test_loggers_change_no_job_and_a_misspelt_key_is_named(tmp_path: Path) -> None:
    plain = sweep_config_from(_config(tmp_path, {}), tmp_path)
    logged = sweep_config_from(_config(tmp_path, {"wandb": {"mode": "offline", "dir": "wb"}, "every_s": 5}), tmp_path)
    assert config_hash(plain) == config_hash(logged)
    assert logged.loggers.wandb is not None and logged.loggers.wandb.dir == (tmp_path / "wb").resolve()
    with pytest.raises(ConfigError, match=r"loggers\.mlflw: unknown key; did you mean 'mlflow'\?"):
        sweep_config_from(_config(tmp_path, {"mlflw": {}}), tmp_path)
    with pytest.raises(ConfigError, match=r"loggers\.wandb\.mode"):
        sweep_config_from(_config(tmp_path, {"wandb": {"mode": "sometimes"}}), tmp_path)


def test_a_tracking_uri_with_credentials_is_refused(tmp_path: Path) -> None:
    secret = {"mlflow": {"tracking_uri": "https://alice:s3cret@mlflow.lab"}}
    with pytest.raises(ConfigError, match=r"loggers\.mlflow\.tracking_uri: .*MLFLOW_TRACKING_USERNAME") as caught:
        sweep_config_from(_config(tmp_path, secret), tmp_path)
    assert "s3cret" not in str(caught.value)
    sweep_config_from(_config(tmp_path, {"mlflow": {"tracking_uri": "https://mlflow.lab:5000"}}), tmp_path)


def test_a_tracker_whose_package_is_missing_names_its_extra(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    module, cls, _, extra = TRACKERS["mlflow"]
    monkeypatch.setitem(TRACKERS, "mlflow", (module, cls, "scratchworld_no_such_package", extra))
    config = sweep_config_from(_config(tmp_path, {"mlflow": {}}), tmp_path)
    with pytest.raises(ConfigError, match=r"^loggers\.mlflow: .* pip install 'scratchworld-dist\[mlflow\]'$"):
        configured_trackers(config.loggers)
    assert configured_trackers(sweep_config_from(_config(tmp_path, {}), tmp_path).loggers) == []
