"""Planning: task hashes cover every byte a worker sees, and job ids change exactly when a result could."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from scratchworld_dist import SuiteError
from scratchworld_dist.kinds.tasks import (
    EpisodeMatrix,
    TaskContent,
    default_episode_clock,
    episode_settings,
    job_id,
    plan_jobs,
    read_task,
)
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import NO_MODEL, JobSpec, worker_job
from scratchworld_dist.sweep import suite_hash as hash_of_suite
from tests.conftest import SUITE_DIR
from tests.support.projects import with_entry
from workers.contract import (
    MIB,
    EpisodeClock,
    LLMSettings,
    ModelSpec,
    ObservationSettings,
    ProjectLimits,
    RateLimits,
    RetryPolicy,
    SyntheticEpisodes,
)
from workers.kinds import kind_fingerprint
from workers.node import harness_fingerprint

GPT = ModelSpec(name="gpt", model="openai/gpt-4o", temperature=0.0, api_key_env="OPENAI_API_KEY")
CLAUDE = ModelSpec(name="claude", model="anthropic/claude-sonnet", max_tokens=1024)


def contents(root: Path) -> list[TaskContent]:
    return [read_task(task) for task in load_suite(root).tasks]


def ids_by_task(jobs: list[JobSpec]) -> dict[tuple[str, str, str, int], str]:
    return {(job.model_name, job.body.mode, job.task_id, job.seed): job.job_id for job in jobs}


def plan(tasks: list[TaskContent], models: list[ModelSpec | None] | None = None) -> list[JobSpec]:
    return list(
        plan_jobs(
            EpisodeMatrix(
                models=models or [GPT, CLAUDE],
                modes=["composite", "primitive"],
                agent="llm",
                tasks=tasks,
                seeds=[0, 1, 2],
                max_steps=30,
            )
        )
    )


@pytest.fixture(scope="module")
def ours() -> list[TaskContent]:
    return contents(SUITE_DIR)


@pytest.fixture
def suite_copy(tmp_path: Path) -> Path:
    root = tmp_path / "tasks"
    shutil.copytree(SUITE_DIR, root)
    return root


# --- the matrix --------------------------------------------------------------------------------


def test_read_task_carries_every_file(ours: list[TaskContent]) -> None:
    assert len(ours) == 12
    content = next(c for c in ours if c.task.id == "sum_two_numbers")
    task = content.task
    assert content.payload.task_id == "sum_two_numbers"
    assert content.payload.category == "compute"
    assert content.payload.instruction == task.instruction
    assert content.payload.initial_project == task.initial_project.read_bytes()
    assert task.golden_project is not None
    assert content.payload.golden_project == task.golden_project.read_bytes()
    assert content.payload.evaluation.script_source == task.evaluation_script.read_text(encoding="utf-8")
    assert content.payload.evaluation.helper_source == (SUITE_DIR / "harness.js").read_text(encoding="utf-8")
    assert len(content.task_hash) == 16
    assert len({c.task_hash for c in ours}) == len(ours)


def test_matrix_size_and_order(ours: list[TaskContent]) -> None:
    jobs = plan(ours)
    assert len(jobs) == 2 * 2 * 3 * len(ours) == 144
    cells = [(j.model_name, j.body.mode, j.seed, j.task_id) for j in jobs]
    task_ids = [c.task.id for c in ours]
    expected = [
        (model, mode, seed, task)
        for model in ("gpt", "claude")
        for mode in ("composite", "primitive")
        for seed in (0, 1, 2)
        for task in task_ids
    ]
    assert cells == expected


def test_job_fields_come_from_the_plan(ours: list[TaskContent]) -> None:
    content = ours[3]
    (job,) = plan_jobs(
        EpisodeMatrix(models=[CLAUDE], modes=["primitive"], agent="llm", tasks=[content], seeds=[4], max_steps=12)
    )
    assert job.model == CLAUDE and job.model_name == "claude"
    assert (job.body.mode, job.agent.name, job.seed, job.body.max_steps) == ("primitive", "llm", 4, 12)
    assert (job.task_id, job.category, job.task_hash) == (content.task.id, content.task.category, content.task_hash)
    assert job.body.observation == ObservationSettings()
    assert job.llm == LLMSettings()
    identity = (content.task_hash, content.task.id, 4, 12, job.body.observation, job.llm)
    assert job.job_id == job_id(CLAUDE, "primitive", "llm", *identity)
    episode = worker_job(job, attempt=1, timeout_s=60)
    assert (episode.observation, episode.llm) == (ObservationSettings(), LLMSettings())


def test_llm_job_identity_covers_what_the_model_sees_not_how_calls_are_paced(ours: list[TaskContent]) -> None:
    def only_id(model: ModelSpec, llm: LLMSettings) -> str:
        (job,) = plan_jobs(
            EpisodeMatrix(
                models=[model], modes=["composite"], agent="llm", tasks=ours[:1], seeds=[0], max_steps=5, llm=llm
            )
        )
        return job.job_id

    base = only_id(CLAUDE, LLMSettings())
    paced = CLAUDE.model_copy(update={"rate_limits": RateLimits(requests_per_minute=10), "api_key_env": "OTHER_KEY"})
    assert only_id(paced, LLMSettings(retry=RetryPolicy(max_attempts=1))) == base
    assert only_id(CLAUDE, LLMSettings(show_action_result=False)) != base
    assert only_id(CLAUDE, LLMSettings(history_messages=5)) != base
    assert only_id(CLAUDE.model_copy(update={"coordinates": "normalized_1000"}), LLMSettings()) != base
    (scripted,) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=["composite"],
            agent="oracle",
            tasks=ours[:1],
            seeds=[0],
            max_steps=5,
            llm=LLMSettings(),
        )
    )
    assert scripted.llm is None


def test_step_limits_per_mode(ours: list[TaskContent]) -> None:
    jobs = list(
        plan_jobs(
            EpisodeMatrix(
                models=[None],
                modes=["composite", "primitive"],
                agent="oracle",
                tasks=ours[:1],
                seeds=[0],
                max_steps={"composite": 9, "primitive": 90},
            )
        )
    )
    assert [(j.body.mode, j.body.max_steps) for j in jobs] == [("composite", 9), ("primitive", 90)]
    assert jobs[0].body.observation is None


def test_observation_settings_change_primitive_ids_only(ours: list[TaskContent]) -> None:
    def ids(settings: ObservationSettings) -> list[str]:
        return [
            j.job_id
            for j in plan_jobs(
                EpisodeMatrix(
                    models=[None],
                    modes=["composite", "primitive"],
                    agent="oracle",
                    tasks=ours[:1],
                    seeds=[0],
                    max_steps=5,
                    observation=settings,
                )
            )
        ]

    default, screen = ids(ObservationSettings()), ids(ObservationSettings(ocr_scope="screen"))
    assert default[0] == screen[0]
    assert default[1] != screen[1]


def test_ids_are_stable_across_planning_calls(ours: list[TaskContent]) -> None:
    first = [j.job_id for j in plan(ours)]
    again = [j.job_id for j in plan(contents(SUITE_DIR))]
    assert first == again


def test_ids_are_unique_across_the_matrix(ours: list[TaskContent]) -> None:
    jobs = plan(ours)
    assert len({j.job_id for j in jobs}) == len(jobs)
    assert all(len(j.job_id) == 24 for j in jobs)


def test_scripted_agents_use_no_model(ours: list[TaskContent]) -> None:
    jobs = list(
        plan_jobs(EpisodeMatrix(models=[None], modes=["composite"], agent="oracle", tasks=ours, seeds=[0], max_steps=5))
    )
    assert len(jobs) == len(ours)
    assert {j.model_name for j in jobs} == {NO_MODEL}
    noop = list(
        plan_jobs(EpisodeMatrix(models=[None], modes=["composite"], agent="noop", tasks=ours, seeds=[0], max_steps=5))
    )
    assert {j.job_id for j in jobs}.isdisjoint(j.job_id for j in noop)


@pytest.mark.parametrize(
    ("field", "value"),
    [("mode", "primitive"), ("agent", "noop"), ("seed", 1), ("max_steps", 31), ("task_hash", "0" * 16)],
)
def test_each_identity_field_changes_the_id(field: str, value: object) -> None:
    base = {"model": GPT, "mode": "composite", "agent": "llm", "task_hash": "a" * 16, "task_id": "t", "seed": 0}
    base["max_steps"] = 30
    changed = {**base, field: value}
    assert job_id(**changed) != job_id(**base)  # type: ignore[arg-type]


def test_the_harness_fingerprint_and_project_limits_are_part_of_the_id() -> None:
    base = job_id(None, "composite", "oracle", "a" * 16, "t", 0, 30)
    episodes = kind_fingerprint(harness_fingerprint(), "tasks").digest  # the core and the episodes' own code
    assert base == job_id(None, "composite", "oracle", "a" * 16, "t", 0, 30, harness=episodes)
    assert base != job_id(None, "composite", "oracle", "a" * 16, "t", 0, 30, harness=harness_fingerprint().digest)
    assert job_id(None, "composite", "oracle", "a" * 16, "t", 0, 30, harness="0" * 16) != base
    smaller = ProjectLimits(max_entry_mb=1)
    assert job_id(None, "composite", "oracle", "a" * 16, "t", 0, 30, project_limits=smaller) != base
    (job,) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=["composite"],
            agent="oracle",
            tasks=contents(SUITE_DIR)[:1],
            seeds=[0],
            max_steps=5,
            project_limits=smaller,
        )
    )
    assert worker_job(job, 1, 60).project_limits == smaller
    assert worker_job(job, 1, 60).harness == episodes


# --- task content changes ----------------------------------------------------------------------


def _flip_last_byte(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[-1] ^= 0x01
    path.write_bytes(bytes(data))


def _append_space(path: Path) -> None:
    path.write_bytes(path.read_bytes() + b" ")


def _edit_instruction(path: Path) -> None:
    task = json.loads(path.read_text(encoding="utf-8"))
    task["instruction"] += "!"
    path.write_text(json.dumps(task), encoding="utf-8")


def _edit_timeout(path: Path) -> None:
    task = json.loads(path.read_text(encoding="utf-8"))
    task["timeout_s"] += 1
    path.write_text(json.dumps(task), encoding="utf-8")


@pytest.mark.parametrize(
    ("file_name", "edit"),
    [
        ("evaluate.js", _append_space),
        ("initial.sb3", _flip_last_byte),
        ("golden.sb3", _flip_last_byte),
        ("task.json", _edit_instruction),
        ("task.json", _edit_timeout),
    ],
)
def test_changing_one_task_changes_only_its_hash_and_ids(
    ours: list[TaskContent], suite_copy: Path, file_name: str, edit: object
) -> None:
    changed_task = "star_shower"
    original = contents(suite_copy)
    assert [c.task_hash for c in original] == [c.task_hash for c in ours]  # the copy is faithful

    edit(suite_copy / "create" / changed_task / file_name)  # type: ignore[operator]
    edited = contents(suite_copy)

    hashes_before = {c.task.id: c.task_hash for c in original}
    hashes_after = {c.task.id: c.task_hash for c in edited}
    assert hashes_after[changed_task] != hashes_before[changed_task]
    assert {k: v for k, v in hashes_after.items() if k != changed_task} == {
        k: v for k, v in hashes_before.items() if k != changed_task
    }
    assert hash_of_suite(edited) != hash_of_suite(original)

    ids_before, ids_after = ids_by_task(plan(original)), ids_by_task(plan(edited))
    assert ids_before.keys() == ids_after.keys()
    for cell, before in ids_before.items():
        if cell[2] == changed_task:
            assert ids_after[cell] != before, cell
        else:
            assert ids_after[cell] == before, cell


def test_changing_the_shared_helper_changes_every_task(suite_copy: Path) -> None:
    original = contents(suite_copy)
    _append_space(suite_copy / "harness.js")
    edited = contents(suite_copy)
    assert all(a.task_hash != b.task_hash for a, b in zip(original, edited, strict=True))


def test_suite_hash_ignores_order_but_not_membership(ours: list[TaskContent]) -> None:
    assert hash_of_suite(list(reversed(ours))) == hash_of_suite(ours)
    assert hash_of_suite(ours[1:]) != hash_of_suite(ours)


# --- model identity ----------------------------------------------------------------------------


def test_model_parameters_change_ids(ours: list[TaskContent]) -> None:
    base = ids_by_task(plan(ours, [GPT]))
    for variant in (
        GPT.model_copy(update={"temperature": 0.7}),
        GPT.model_copy(update={"model": "openai/gpt-4o-mini"}),
        GPT.model_copy(update={"max_tokens": 256}),
        GPT.model_copy(update={"api_base": "http://localhost:4000"}),
        GPT.model_copy(update={"params": {"top_p": 0.5}}),
    ):
        changed = ids_by_task(plan(ours, [variant]))
        assert set(changed.values()).isdisjoint(base.values()), variant


def test_model_label_and_key_variable_do_not_change_ids(ours: list[TaskContent]) -> None:
    base = [j.job_id for j in plan(ours, [GPT])]
    renamed = GPT.model_copy(update={"name": "gpt-4o (prod)", "api_key_env": "OTHER_KEY"})
    assert [j.job_id for j in plan(ours, [renamed])] == base
    unkeyed = GPT.model_copy(update={"api_key_env": None})
    assert [j.job_id for j in plan(ours, [unkeyed])] == base


def test_episode_carries_the_job(ours: list[TaskContent]) -> None:
    job = plan(ours)[17]
    episode = worker_job(job, attempt=3, timeout_s=120.0)
    assert episode.job_id == job.job_id
    assert episode.attempt == 3
    assert episode.timeout_s == 120.0
    assert (episode.task_id, episode.mode, episode.agent) == (job.task_id, job.body.mode, job.agent)
    assert (episode.model, episode.seed, episode.max_steps) == (job.model, job.seed, job.body.max_steps)


def test_the_demo_config_plans_our_whole_suite_for_the_oracle() -> None:
    from scratchworld_dist._run import plan_run
    from scratchworld_dist.sweep import load_sweep_config

    config = load_sweep_config(SUITE_DIR.parent / "configs" / "demo.yaml")
    planned = plan_run(config)
    modes = episode_settings(config).modes
    assert (config.agent.name, modes, config.seeds) == ("oracle", ["composite", "primitive"], [0])
    assert config.suite == SUITE_DIR
    for mode in modes:
        tasks = sorted(job.task_id for job in planned.jobs if job.body.mode == mode)
        assert tasks == sorted(task.id for task in load_suite(SUITE_DIR).tasks)
    assert all(content.payload.golden_project for content in planned.contents)  # the oracle needs every golden


def test_a_task_project_over_the_limits_fails_the_plan_naming_its_file(suite_copy: Path) -> None:
    task = load_suite(suite_copy).task("sum_two_numbers")
    bomb = with_entry(task.initial_project.read_bytes(), "huge.wav", bytes(2 * MIB))
    task.initial_project.write_bytes(bomb)
    assert read_task(task).payload.initial_project == bomb  # fine under the defaults
    with pytest.raises(SuiteError, match=r"initial.sb3: the entry 'huge.wav' is 2.00 MiB, over the limit of 1 MiB"):
        read_task(task, limits=ProjectLimits(max_entry_mb=1))
    with pytest.raises(SuiteError, match=r"initial.sb3: the project is .* over project_limits.max_file_mb"):
        read_task(task, limits=ProjectLimits(max_file_mb=0.01))


def test_a_synthetic_stand_in_never_shares_an_id_with_the_real_job(ours: list[TaskContent]) -> None:
    real = {
        job.task_id: job.job_id
        for job in plan_jobs(
            EpisodeMatrix(models=[None], modes=["composite"], agent="oracle", tasks=ours, seeds=[0], max_steps=5)
        )
    }
    mixed = SyntheticEpisodes(tasks=["sum_two_numbers"])
    planned = {
        job.task_id: job.job_id
        for job in plan_jobs(
            EpisodeMatrix(
                models=[None], modes=["composite"], agent="oracle", tasks=ours, seeds=[0], max_steps=5, synthetic=mixed
            )
        )
    }
    assert planned["sum_two_numbers"] != real["sum_two_numbers"]
    assert {k: v for k, v in planned.items() if k != "sum_two_numbers"} == {
        k: v for k, v in real.items() if k != "sum_two_numbers"
    }


def test_a_virtual_episode_clock_and_each_of_its_durations_change_the_job_id(ours: list[TaskContent]) -> None:
    def ids(clock: EpisodeClock | None) -> list[str]:
        return [
            job.job_id
            for job in plan_jobs(
                EpisodeMatrix(
                    models=[None],
                    modes=["primitive"],
                    agent="oracle",
                    tasks=ours[:2],
                    seeds=[0],
                    max_steps=9,
                    episode_clock=clock,
                )
            )
        ]

    real = ids(None)
    assert ids(EpisodeClock(mode="real", settle_ms=900)) == real  # real-clock ids stay as they were
    virtual = ids(EpisodeClock.model_validate("virtual"))
    assert set(virtual).isdisjoint(real)
    for change in ({"settle_ms": 400}, {"think_ms": 5000}, {"start_ms": 2000}):
        assert set(ids(EpisodeClock(mode="virtual", **change))).isdisjoint(virtual)
    (job, *_) = plan_jobs(
        EpisodeMatrix(
            models=[None],
            modes=["composite"],
            agent="oracle",
            tasks=ours[:1],
            seeds=[0],
            max_steps=9,
            episode_clock=EpisodeClock(mode="virtual"),
        )
    )
    assert worker_job(job, 1, 60).episode_clock.mode == "virtual"  # the worker gets the clock it was planned with


def test_the_episode_clock_defaults_to_virtual() -> None:
    assert default_episode_clock().mode == "virtual"
    with pytest.raises(ValueError, match="start_ms"):
        EpisodeClock(mode="virtual", start_ms=100)  # the editor's panels need 500 ms to catch up
