"""Admission: browser slots derived from what a waiting editor is measured to cost, and workers that
decline jobs while their node is short of memory (a real memory hog, a real local Ray)."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import psutil
import pytest
import ray

from scratchworld_dist.kinds.tasks import EpisodeMatrix, plan_jobs, read_task
from scratchworld_dist.scheduling import Scheduler, WorkerPool, admitted_slots, most_slots, pages_per_worker
from scratchworld_dist.suites import load_suite
from scratchworld_dist.sweep import JobSpec, Limits, worker_job
from tests.conftest import REPO, pooled_editor
from tests.support.cli_runner import invoke
from workers.contract import MIB, AgentRef, EpisodeClock, JobResult, ModelSpec, SyntheticEpisodes
from workers.editor import EditorPool, cached_editor_cost, measure_editor_cost
from workers.editor._cost import cost_cache_path
from workers.kinds import kind_fingerprint
from workers.node import (
    DELIVERED_PER_CORE,
    PRIMITIVE_DELIVERED_PER_CORE,
    EditorCost,
    NodeMemory,
    derive_slots,
    harness_fingerprint,
    node_memory,
)

GIB = 1024 * MIB
NODE = NodeMemory(total_bytes=24 * GIB, available_bytes=20 * GIB)


def cost(cpu: float, pss_mb: int, clock: str = "virtual") -> EditorCost:
    return EditorCost(clock=clock, cpu_cores=cpu, pss_bytes=pss_mb * MIB)  # type: ignore[arg-type]


def test_slots_are_the_fewer_of_what_cpu_and_memory_allow_less_the_margin() -> None:
    # Real clock: a waiting page steps its VM, the CPU binds: 2 cores x 0.75 / 0.25 = 6.
    real = derive_slots(cost(0.25, 300, "real"), cores=2, memory=NODE, margin=0.25, reserve_bytes=GIB)
    assert (real.by_cpu, real.slots) == (6, 6)
    # Virtual clock: the page stands still; memory allows (20 - 1) GiB x 0.75 / 300 MiB = 48, the CPU 150, and
    # what the node delivers binds: DELIVERED_PER_CORE per core.
    virtual = derive_slots(cost(0.01, 300), cores=2, memory=NODE, margin=0.25, reserve_bytes=GIB)
    delivered = 2 * DELIVERED_PER_CORE
    assert (virtual.by_memory, virtual.by_cpu, virtual.by_throughput) == (48, 150, delivered)
    assert virtual.slots == min(48, delivered)
    assert f"{virtual.slots} browser slot(s)" in virtual.describe() and f"throughput {delivered}" in virtual.describe()
    # On a bigger node memory binds again: (20 - 1) GiB x 0.75 / 300 MiB = 48 on 16 cores; a larger margin and a
    # bigger editor take slots away.
    assert derive_slots(cost(0.01, 300), cores=16, memory=NODE, margin=0.25, reserve_bytes=GIB).slots == 48
    assert derive_slots(cost(0.01, 300), cores=16, memory=NODE, margin=0.5, reserve_bytes=GIB).slots == 32
    assert derive_slots(cost(0.01, 600), cores=16, memory=NODE, margin=0.25, reserve_bytes=GIB).slots == 24
    assert (
        derive_slots(cost(0.0, 10), cores=64, memory=NODE, margin=0, reserve_bytes=0).slots == 64 * DELIVERED_PER_CORE
    )
    # A node whose memory is all reserved still runs one episode at a time.
    starved = NodeMemory(total_bytes=4 * GIB, available_bytes=GIB // 2)
    assert derive_slots(cost(0.01, 300), cores=2, memory=starved, margin=0.25, reserve_bytes=GIB).slots == 1


def test_primitive_episodes_get_the_slots_the_node_delivers_in_primitive_mode() -> None:
    composite = derive_slots(cost(0.01, 200), cores=2, memory=NODE, margin=0.25, reserve_bytes=GIB)
    primitive = derive_slots(cost(0.01, 200), cores=2, memory=NODE, margin=0.25, reserve_bytes=GIB, mode="primitive")
    assert PRIMITIVE_DELIVERED_PER_CORE < DELIVERED_PER_CORE
    assert (composite.slots, primitive.slots) == (2 * DELIVERED_PER_CORE, 2 * PRIMITIVE_DELIVERED_PER_CORE)
    assert f"throughput {primitive.slots} ({PRIMITIVE_DELIVERED_PER_CORE} per core in primitive mode" in (
        primitive.describe()
    )


def jobs(
    model: ModelSpec | None, clock: str = "virtual", harness: str = "h", modes: tuple[str, ...] = ("composite",)
) -> list[JobSpec]:
    contents = [read_task(task) for task in load_suite(REPO / "tasks").tasks[:2]]
    episode_clock = EpisodeClock(mode=clock)  # type: ignore[arg-type]
    agent = AgentRef(name="llm" if model else "oracle")
    return list(
        plan_jobs(
            EpisodeMatrix(
                models=[model],
                modes=list(modes),  # type: ignore[arg-type]
                agent=agent,
                tasks=contents,
                seeds=[0],
                max_steps=5,
                harness=harness,
                episode_clock=episode_clock,
            )
        )
    )


def test_agents_without_a_model_keep_one_episode_per_core_and_explicit_slots_win(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))  # nothing measured: measuring would open a browser
    said: list[str] = []
    assert admitted_slots(Limits(), jobs(None), "h", said.append) == os.cpu_count()
    assert admitted_slots(Limits(browser_slots=5), jobs(ModelSpec(name="m", model="openai/m")), "h", said.append) == 5
    assert said == [] and not cost_cache_path().exists()
    assert pages_per_worker(Limits(), 40, 2) == 20 and pages_per_worker(Limits(), 1, 2) == 1
    assert pages_per_worker(Limits(pages_per_worker=3), 40, 2) == 3


def test_model_jobs_get_slots_from_the_cost_measured_for_their_clock(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    harness = harness_fingerprint().digest
    path = cost_cache_path()
    path.parent.mkdir(parents=True)
    known = {"virtual": cost(0.01, 200).model_copy(update={"harness": harness}), "real": cost(0.5, 200, "real")}
    path.write_text("{" + ",".join(f'"{k}": {v.model_dump_json()}' for k, v in known.items()) + "}")
    said: list[str] = []
    model = ModelSpec(name="m", model="openai/m")
    slots = admitted_slots(Limits(), jobs(model, "virtual"), harness, said.append)
    expected = derive_slots(
        known["virtual"], cores=os.cpu_count() or 1, memory=node_memory(), margin=0.25, reserve_bytes=GIB
    )
    assert abs(slots - expected.slots) <= 1  # the node's free memory moved a little in between
    assert len(said) == 1 and "virtual clock" in said[0] and "in composite mode" in said[0]
    # One primitive job among composite ones: the node holds what it delivers in primitive mode.
    mixed = admitted_slots(Limits(), jobs(model, "virtual", modes=("composite", "primitive")), harness, said.append)
    cores = os.cpu_count() or 1
    assert mixed == min(slots, cores * PRIMITIVE_DELIVERED_PER_CORE) and "in primitive mode" in said[-1]
    assert cached_editor_cost("virtual", harness) == known["virtual"]  # read back, not measured again


def test_a_private_ray_started_before_admission_offers_every_slot_admission_can_give(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A sweep starts its private Ray beside the preflight, before its jobs are settled, offering ``most_slots``:
    admission never gives more, even for an editor that costs nothing (the bound is reached there)."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    harness = harness_fingerprint().digest
    cost_cache_path().parent.mkdir(parents=True)
    free = cost(0.0, 1).model_copy(update={"harness": harness})
    cost_cache_path().write_text(f'{{"virtual": {free.model_dump_json()}}}')
    model = ModelSpec(name="m", model="openai/m")
    cores = os.cpu_count() or 1
    for limits in (Limits(), Limits(browser_slots=5), Limits(browser_slots=500)):
        given = [
            admitted_slots(limits, planned, harness, lambda _: None)
            for planned in (jobs(model), jobs(model, modes=("primitive",)), jobs(None))
        ]
        assert max(given) <= most_slots(limits, cores), (limits, given)
    assert admitted_slots(Limits(), jobs(model), harness, lambda _: None) == most_slots(Limits(), cores)


def test_the_capacity_command_prints_a_nodes_slots_from_its_measured_cost(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    measured = cost(0.25, 300, "real").model_copy(update={"harness": harness_fingerprint().digest})
    cost_cache_path().parent.mkdir(parents=True)
    cost_cache_path().write_text(f'{{"real": {measured.model_dump_json()}}}')
    done = invoke("capacity", "--clock", "real", "--margin", "0.5")
    expected = derive_slots(measured, cores=os.cpu_count() or 1, memory=node_memory(), margin=0.5, reserve_bytes=GIB)
    assert done.returncode == 0, done.stderr
    assert "0.250 core(s) and 300 MB PSS on the real clock" in done.stdout
    assert f"""--resources='{{"browser": {expected.slots}}}'""" in done.stdout
    primitive = invoke("capacity", "--clock", "real", "--mode", "primitive")
    slots = derive_slots(
        measured, cores=os.cpu_count() or 1, memory=node_memory(), margin=0.25, reserve_bytes=GIB, mode="primitive"
    ).slots
    assert "per core in primitive mode" in primitive.stdout and f'{{"browser": {slots}}}' in primitive.stdout
    refused = invoke("capacity", "--margin", "1")
    assert refused.returncode == 2 and "--margin" in refused.stderr and len(refused.stderr.splitlines()) == 1


@pytest.mark.browser
@pytest.mark.slow
async def test_a_waiting_editor_costs_less_cpu_on_the_virtual_clock(shared_pool: EditorPool) -> None:
    """Measured on real editors: a paused page does not step its VM; either takes a few hundred MB.

    Only the measuring browser counts: an editor of this process's other browser, lent meanwhile on the
    real clock (about what a real-clock page costs), once made the virtual page look as costly.
    """
    async with pooled_editor(shared_pool):
        virtual = await measure_editor_cost("virtual", editors=1)  # one each: a tenfold gap, whatever the noise
        real = await measure_editor_cost("real", editors=1)
    assert real.cpu_cores > 0.1  # the VM steps at 30 frames per second
    assert virtual.cpu_cores < real.cpu_cores / 2
    for measured in (virtual, real):
        assert 50 * MIB < measured.pss_bytes < 2 * GIB


@pytest.fixture
def memory_hog() -> Iterator[subprocess.Popen[str]]:
    """A process that holds 2 GiB of touched memory until killed (the kernel counts it as used)."""
    script = (
        "import sys\nm = bytearray(2 << 30)\nm[::4096] = b'1' * ((2 << 30) // 4096)\n"
        "print('held', flush=True)\nsys.stdin.read()\n"
    )
    with subprocess.Popen(
        [sys.executable, "-c", script], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True
    ) as hog:
        yield hog
        hog.kill()


@pytest.mark.ray
def test_workers_take_no_job_while_the_node_is_short_of_memory(
    shared_ray: int, memory_hog: subprocess.Popen[str]
) -> None:
    # The reserve sits 1 GiB under what is free now; the hog takes 2 GiB, so workers decline jobs.
    reserve = node_memory().available_bytes - GIB
    assert memory_hog.stdout is not None and memory_hog.stdout.readline().strip() == "held"
    assert node_memory().available_bytes < reserve
    planned = jobs(None, harness=kind_fingerprint(harness_fingerprint(), "tasks").digest)  # what workers check
    pool = WorkerPool(2, 1, SyntheticEpisodes(duration_s=0.1), memory_reserve_bytes=reserve)
    payloads = {job.task_id: ray.put(read_task_payload(job)) for job in planned}
    finished: list[JobResult] = []
    scheduler = Scheduler(
        pool, payloads, timeout_s=120, retries=0, on_result=lambda _, r: finished.append(r), sends=worker_job
    )
    driver = threading.Thread(target=scheduler.run, args=([(job, 1) for job in planned],))
    try:
        driver.start()
        deadline = time.monotonic() + 300  # a hang detector: Ray starts the workers slowly on a loaded machine
        while scheduler.stats.paused < len(pool):  # every worker has declined and waits for memory
            assert time.monotonic() < deadline, scheduler.stats
            time.sleep(0.05)
        assert finished == [] and scheduler.stats.attempts == 0
        memory_hog.kill()  # memory is back: the same jobs start, as their first attempt
        driver.join(timeout=300)  # a hang detector, as above
        assert not driver.is_alive()
    finally:
        pool.close()
    assert sorted(r.job_id for r in finished) == sorted(job.job_id for job in planned)
    assert all(r.outcome == "passed" and r.attempt == 1 for r in finished)
    assert scheduler.stats.declined >= len(pool)
    for result in finished:  # each result says what the worker and its node had as it ended, judged by the reserve
        load = result.load
        assert load is not None and load.node_available_bytes > 0
        assert load.admits == (load.node_available_bytes >= reserve)  # other tests' browsers may hold memory now


@pytest.mark.ray
def test_a_run_starts_no_more_workers_than_it_can_keep_busy(shared_ray: int) -> None:
    """Each worker launches a browser and opens editors: a one-job run on two slots starts one."""
    sizes = {}
    for pages, at_once in [(1, 1), (1, 2), (1, 7), (1, None), (2, 1), (2, 3)]:
        pool = WorkerPool(2, pages, SyntheticEpisodes(), at_once=at_once)
        try:
            sizes[pages, at_once] = len(pool)
        finally:
            pool.close()
    assert sizes == {(1, 1): 1, (1, 2): 2, (1, 7): 2, (1, None): 2, (2, 1): 1, (2, 3): 1}


@pytest.mark.ray
def test_a_kept_pool_serves_the_next_sweep_of_its_kind_and_no_other(shared_ray: int) -> None:
    """Workers left by ``close(keep=True)`` are the next pool's when it is built alike (fewer wanted: the
    rest are killed); a pool of another kind kills them first, so they never hold its browser slots."""

    def pids(pool: WorkerPool) -> list[int]:
        return [info.pid for info in ray.get([handle.info.remote() for handle in pool.handles], timeout=60)]

    def exits(pid: int) -> bool:
        try:
            return psutil.wait_procs([psutil.Process(pid)], timeout=60)[1] == []
        except psutil.NoSuchProcess:
            return True

    first = WorkerPool(2, 1, SyntheticEpisodes())
    started = pids(first)
    first.close(keep=True)
    again = WorkerPool(2, 1, SyntheticEpisodes())
    assert (again.reused, pids(again)) == (2, started)
    assert again.describe(2).endswith("on 2 browser slot(s), 2 kept warm from this process's last sweep")
    again.close(keep=True)
    fewer = WorkerPool(2, 1, SyntheticEpisodes(), at_once=1)
    assert (fewer.reused, pids(fewer)) == (1, started[:1])
    assert exits(started[1])  # the one not wanted is killed
    fewer.close(keep=True)
    other = WorkerPool(2, 2, SyntheticEpisodes())  # two pages per worker: both slots, no kept worker left
    try:
        assert other.reused == 0 and pids(other)[0] not in started
        assert exits(started[0])
    finally:
        other.close()
    last = WorkerPool(2, 2, SyntheticEpisodes())
    try:
        assert last.reused == 0  # closed without keep: nothing kept
    finally:
        last.close()


def read_task_payload(job: JobSpec) -> object:
    suite = load_suite(REPO / "tasks")
    (task,) = [task for task in suite.tasks if task.id == job.task_id]
    return read_task(task).payload
