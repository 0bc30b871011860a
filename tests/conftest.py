"""Shared fixtures: one real Chromium for the whole run, project and suite builders."""

from __future__ import annotations

import contextlib
import os
import shutil
import sys
from collections import Counter
from collections.abc import AsyncIterator, Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from tests.support.retries import PROPERTY, SecondLooks
from workers.actor import WorkerBrowser
from workers.editor import BrowserSession, Editor, EditorPool
from workers.evaluation import Evaluator
from workers.kinds.tasks import EpisodeRunner
from workers.node import OWN_FILES

# Pytest keeps each test module's assertion-rewritten bytecode in __pycache__ only while bytecode writing is on,
# and environments that set PYTHONDONTWRITEBYTECODE (this machine's does) turn it off: every run, in each xdist
# worker, would rewrite all the test modules again (collection 33 s against 10 s here). The flag is this
# process's own: subprocesses and Ray's workers keep their environment's choice.
sys.dont_write_bytecode = False

if TYPE_CHECKING:
    from tests.support.openai_server import OpenAIServer
    from tests.support.sweep_driver import Driver

REPO = Path(__file__).resolve().parents[1]
SUITE_DIR = REPO / "tasks"
UPSTREAM_DIR = Path(os.environ.get("SCRATCHWORLD_UPSTREAM_DATA", REPO.parent / "shared" / "scratchworld-upstream"))
DATA = Path(__file__).resolve().parent / "data"


def copy_page_files(gui_dir: Path, names: tuple[str, ...] = OWN_FILES) -> None:
    """Our page files (``scratch-gui/`` paths, subfolders included) into another editor folder."""
    for name in names:
        (gui_dir / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(REPO / "scratch-gui" / name, gui_dir / name)


def link_installed_packages(gui_dir: Path) -> None:
    """The npm installs (the editor bundle, the bare page's packages and build) linked into another editor folder."""
    for name in ("node_modules", "bare/node_modules", "bare/build"):
        (gui_dir / name).parent.mkdir(parents=True, exist_ok=True)
        (gui_dir / name).symlink_to(REPO / "scratch-gui" / name)


BROWSER_FIXTURES = frozenset({"session", "shared_pool", "evaluator", "fresh_evaluator", "episode_runner"})
RAY_FIXTURES = frozenset({"shared_ray", "model_ray"})
UPSTREAM_FIXTURE = "upstream_dir"
"""What every test reading ../shared uses, directly or through another fixture (``upstream_clone``...)."""


UPSTREAM_WIDE_TIMEOUT_S = 1800
"""The ceiling of a slow test that reads upstream: it goes over all of upstream's tasks, so its time is upstream's
size's (the composite oracle's test: 333 s alone on a busy machine), not ours; the rest have pyproject's 600 s."""


MARKER_SECONDS = {"slow": 20.0, "ray": 4.0, "browser": 2.0}
"""Roughly what a test with the marker takes on 2 cores; a test with none takes next to nothing."""


def expected_seconds(item: pytest.Item) -> float:
    return max((MARKER_SECONDS[m.name] for m in item.iter_markers() if m.name in MARKER_SECONDS), default=0.05)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """A test that uses the shared browser (or Ray) is a browser (ray) test, whichever module it is in;
    one that reads upstream's data (``upstream_dir``, however it gets it) is an upstream test.

    Modules are then ordered by the time their markers promise, longest first: the parallel run
    (``-n 2 --dist loadfile``, pyproject) hands out whole modules in this order, so the last
    ones to start are short and neither worker idles long at the end.
    """
    for item in items:
        fixtures = set(getattr(item, "fixturenames", ()))
        if BROWSER_FIXTURES & fixtures:
            item.add_marker(pytest.mark.browser)
        if RAY_FIXTURES & fixtures:
            item.add_marker(pytest.mark.ray)
        if UPSTREAM_FIXTURE in fixtures:
            item.add_marker(pytest.mark.upstream)
            if item.get_closest_marker("slow") and not item.get_closest_marker("timeout"):
                item.add_marker(pytest.mark.timeout(UPSTREAM_WIDE_TIMEOUT_S))
    modules: Counter[Path] = Counter()  # by path: modules in different folders may share a name
    for item in items:
        modules[item.path] += expected_seconds(item)
    items.sort(key=lambda item: -modules[item.path])  # stable: a module's own order stays


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    """Every second look a test took at a load-sensitive reference (``second_looks``), passed or failed."""
    looks = {
        report.nodeid: notes
        for reports in terminalreporter.stats.values()
        for report in reports
        if getattr(report, "when", None) == "call"
        and (notes := [value for name, value in getattr(report, "user_properties", ()) if name == PROPERTY])
    }
    if looks:
        terminalreporter.section("second looks at real-clock references")
        for nodeid, notes in sorted(looks.items()):
            for note in notes:
                terminalreporter.line(f"{nodeid}: {note}")


@pytest.fixture
def second_looks(request: pytest.FixtureRequest) -> SecondLooks:
    """Where a test records each second look at a real-clock reference (tests/support/retries.py)."""
    return SecondLooks(request.node)


@pytest.fixture(scope="session")
async def session() -> AsyncIterator[BrowserSession]:
    """One browser for every test that needs an editor (each editor still gets an origin of its own)."""
    async with BrowserSession() as browser:
        yield browser


@pytest.fixture(scope="session")
async def shared_pool(session: BrowserSession) -> AsyncIterator[EditorPool]:
    """The run's editors, reused when they recycle clean: for evaluations, episodes and tests' own pages.

    Opening an editor costs ten times what most evaluations do, so tests share them; whether reuse is
    safe is what test_editor_pool.py and test_agent_editor_recycling.py (tests/workers/editor/) check.
    """
    async with EditorPool(session, spare=0) as pool:
        yield pool


@pytest.fixture(scope="session")
def evaluator(session: BrowserSession, shared_pool: EditorPool) -> Evaluator:
    """Evaluations as workers run them, in ``shared_pool``'s editors (``fresh_evaluator``: a fresh page each)."""
    return Evaluator(session, shared_pool)


@contextlib.asynccontextmanager
async def pooled_editor(pool: EditorPool) -> AsyncIterator[Editor]:
    """An editor of ``pool`` that a test drives itself, recycled afterwards as a runner's is.

    A use is booked as runners book an episode: the pool closes a page returned unused. A test may use
    the default project's palette without loading a project, so a fresh page's is drawn (the pool's
    own uses all load one first, which draws that project's).
    """
    async with pool.editor() as editor:
        editor.uses += 1
        await editor.draw_palette()
        yield editor


@contextlib.asynccontextmanager
async def primitive_editor(pool: EditorPool, sb3: bytes) -> AsyncIterator[Editor]:
    """A ``pooled_editor`` as primitive episodes get it: ``sb3`` loaded, the small stage."""
    async with pooled_editor(pool) as editor:
        await editor.load_project(sb3)
        await editor.set_stage_size("small")
        yield editor


@pytest.fixture(scope="session")
async def episode_runner(session: BrowserSession, shared_pool: EditorPool) -> AsyncIterator[EpisodeRunner]:
    """Episodes as workers run them: agent and evaluation pages from ``shared_pool``, recycled.

    Whether a recycled agent page starts an episode as a fresh one would is what
    tests/workers/editor/test_agent_editor_recycling.py checks; a test of a fresh page or of a runner's
    own pool makes its own ``EpisodeRunner``.
    """
    runner = EpisodeRunner(WorkerBrowser(session, shared_pool))
    yield runner
    await runner.browser.close()


@pytest.fixture(scope="session")
def fresh_evaluator(session: BrowserSession) -> Evaluator:
    """Every evaluation in a new editor (tests of what a fresh page does, e.g. its ready time)."""
    return Evaluator(session)


@pytest.fixture
def upstream_dir() -> Path:
    """The upstream benchmark's data (tasks and projects, no scripts); skip when absent."""
    if not (UPSTREAM_DIR / "tasks").is_dir():
        pytest.skip(f"upstream data not found at {UPSTREAM_DIR}")
    return UPSTREAM_DIR


@pytest.fixture
def fake_clone(tmp_path: Path) -> Path:
    """A clone in upstream's layout with three tasks of ours (tests/support/fake_clone.py); never skipped."""
    from tests.support.fake_clone import fake_clone as write_clone

    return write_clone(tmp_path / "ScratchWorld")


@pytest.fixture
def upstream_clone(tmp_path: Path, upstream_dir: Path) -> Path:
    """A clone-shaped folder: upstream's tasks and projects (symlinked) plus scripts written here, for tests of
    upstream's real tasks (a test of the layout alone takes ``fake_clone``)."""
    clone = tmp_path / "ScratchWorld"
    (clone / "scratch-gui").mkdir(parents=True)
    (clone / "scratch-gui" / "static").symlink_to(upstream_dir / "scratch-gui" / "static")
    shutil.copytree(upstream_dir / "tasks", clone / "tasks")
    scripts = clone / "scratch-bench-api" / "api" / "evaluation_scripts"
    shutil.copytree(DATA / "upstream_scripts", scripts)
    # Every task without a script of ours gets one that only checks the project loaded.
    for task_file in (clone / "tasks").glob("*/*.json"):
        script = scripts / f"{task_file.stem}.js"
        if not script.exists():
            script.write_text((DATA / "loads_only.js").read_text())
    return clone


@pytest.fixture(scope="module")
def shared_ray() -> Iterator[int]:
    """One private local Ray for a module's drivers run in this process (``tests.support.sweep_driver.run_here``).

    It is started as ``scratchworld run`` starts its own, and a driver that finds Ray running uses
    it, so the module pays for one Ray instead of one per run. Yields its browser slots.
    """
    from scratchworld_dist.scheduling import ray_runtime

    with ray_runtime(None, None) as slots:
        yield slots


MODEL_KEY = "sk-test-0b7e4c2a91"
"""The API key ``model_server`` puts in the environment (tests check that it reaches no file and no log)."""


@pytest.fixture(scope="module")
def model_server() -> Iterator[OpenAIServer]:
    """A module's OpenAI-compatible server (``reset`` it per test), its address and ``MODEL_KEY`` in the
    environment (``SCRATCHWORLD_LLM_BASE_URL``, ``SCRATCHWORLD_LLM_API_KEY``) while the module runs."""
    from tests.support.openai_server import OpenAIServer

    with OpenAIServer() as running, pytest.MonkeyPatch.context() as patch:
        patch.setenv("SCRATCHWORLD_LLM_BASE_URL", running.url)
        patch.setenv("SCRATCHWORLD_LLM_API_KEY", MODEL_KEY)
        yield running


@pytest.fixture(scope="module")
def model_ray(model_server: OpenAIServer) -> Iterator[int]:
    """``shared_ray`` for drivers whose workers call ``model_server``: started once the server is in the
    environment, since workers find a model's address and key in theirs, as on a node."""
    from scratchworld_dist.scheduling import ray_runtime

    with ray_runtime(None, None) as slots:
        yield slots


@pytest.fixture
def drivers() -> Iterator[list[Driver]]:
    """Sweep drivers started by a test; each is killed with its process group afterwards."""

    started: list[Driver] = []
    yield started
    for driver in started:
        driver.kill_group()


@pytest.fixture(scope="module")
async def litellm_clients() -> AsyncIterator[None]:
    """LiteLLM imported off the loop, and its HTTP sessions closed before the event loop ends."""
    from workers.llm import close_litellm_clients, load_litellm

    await load_litellm()
    yield
    await close_litellm_clients()
