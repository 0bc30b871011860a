"""The one entry-point registry behind the driver's kinds, the worker's kinds and the agents (``workers.Registry``):
objects in the order of the rank they declare, then plugins by name; a plugin that fails to import, or fails the
caller's check, is one line naming its entry point, in whichever registry reads it. The plugins are real
packages, installed with pip into folders of their own put on the path."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest

from scratchworld_dist.kinds import UnknownKindError, job_kinds, kind_names
from scratchworld_dist.kinds._registry import _registered
from tests.support.plugins import install_plugin
from workers import PLUGIN_RANK, Registry
from workers._registry import group_entry_points
from workers.agent_api import agent_class, registered_agents
from workers.contract import AgentUnavailableError
from workers.kinds import KindRegistryError, worker_kinds

THINGS = '''
class Thing:
    """An entry of a test group: named, and ranked if it says so."""

    def __init__(self, name, rank=None):
        self.name = name
        if rank is not None:
            self.rank = rank


SECOND = Thing("second", 1)
FIRST = Thing("first", 0)
ZEBRA = Thing("zebra")
APPLE = Thing("apple")
STRANGER = Thing("someone else")
'''

BROKEN = 'raise RuntimeError("the plugin is broken\\n  on a second line\\n\\n  and a third")\n'

ONE_LINE = "RuntimeError: the plugin is broken on a second line and a third"
"""What the registries say of BROKEN's failure: its type and its words, on one line."""

GROUP = "scratchworld_tests.things"


class ThingError(Exception):
    """The error class a test registry is given."""


@pytest.fixture(scope="module")
def things(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A package registering ranked and unranked things, a broken and a misnamed one (each in a group of its
    own), and a broken perception agent (which only a lookup of that name loads)."""
    return install_plugin(
        tmp_path_factory.mktemp("things"),
        "registry-things",
        {"registry_things": THINGS, "registry_broken": BROKEN},
        {
            GROUP: {
                "second": "registry_things:SECOND",
                "zebra": "registry_things:ZEBRA",
                "first": "registry_things:FIRST",
                "apple": "registry_things:APPLE",
            },
            "scratchworld_tests.broken": {"broken": "registry_broken:THING"},
            "scratchworld_tests.misnamed": {"misnamed": "registry_things:STRANGER"},
            "scratchworld.perception_agents": {"broken": "registry_broken:Agent"},
        },
    )


@pytest.fixture
def on_path(things: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.syspath_prepend(str(things))
    return things


@pytest.fixture(scope="module")
def broken_kinds(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A package registering a broken kind on both sides (which breaks listing the kinds: a test's own path)."""
    return install_plugin(
        tmp_path_factory.mktemp("broken-kinds"),
        "broken-kinds",
        {"broken_kind": BROKEN},
        {
            "scratchworld.kinds": {"broken": "broken_kind:KIND"},
            "scratchworld.worker_kinds": {"broken": "broken_kind:KIND"},
        },
    )


@pytest.fixture
def broken_on_path(broken_kinds: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[Path]:
    monkeypatch.syspath_prepend(str(broken_kinds))
    _registered.cache_clear()  # the driver's kinds are read once per process
    yield broken_kinds
    _registered.cache_clear()


def accept(name: str, found: object) -> str | None:
    return None


@pytest.mark.usefixtures("on_path")
def test_ranked_objects_come_first_by_rank_and_the_others_by_name() -> None:
    registry: Registry[object] = Registry(GROUP, "thing", ThingError, accept)
    assert list(registry.load_all()) == ["first", "second", "apple", "zebra"]
    assert registry.names() == ["apple", "first", "second", "zebra"]  # listing loads nothing and sorts by name
    assert [getattr(kind, "rank", PLUGIN_RANK) for kind in job_kinds()] == [0, 10, 20, 30]
    assert kind_names() == ["tasks", "drag", "perception", "audit"]  # as each built-in kind declares


@pytest.mark.usefixtures("on_path")
def test_a_plugin_that_fails_to_import_or_to_pass_the_check_is_one_line_naming_its_entry_point() -> None:
    with pytest.raises(ThingError) as caught:
        Registry("scratchworld_tests.broken", "thing", ThingError, accept).load_all()
    assert str(caught.value) == f"thing broken (registry_broken:THING) cannot be imported: {ONE_LINE}"
    assert isinstance(caught.value.__cause__, RuntimeError)

    def named(name: str, found: object) -> str | None:
        called = getattr(found, "name", None)
        return None if called == name else f"is called {called!r}"

    with pytest.raises(ThingError) as caught:
        Registry("scratchworld_tests.misnamed", "thing", ThingError, named).load_all()
    assert str(caught.value) == "thing misnamed (registry_things:STRANGER) is called 'someone else'"


@pytest.mark.usefixtures("on_path")
def test_a_broken_agent_is_one_line_and_breaks_no_other_agent_of_its_kind() -> None:
    assert "broken" in registered_agents("perception")  # listed without being imported
    with pytest.raises(AgentUnavailableError) as caught:
        agent_class("broken", "perception")
    assert str(caught.value) == f"agent broken (registry_broken:Agent) cannot be imported: {ONE_LINE}"
    assert agent_class("oracle", "perception").__name__ == "OraclePerceptionAgent"


@pytest.mark.usefixtures("broken_on_path")
def test_a_broken_kind_is_one_line_on_either_side_and_for_the_agents_it_would_serve() -> None:
    with pytest.raises(UnknownKindError) as driver:
        job_kinds()
    assert str(driver.value) == f"benchmark broken (broken_kind:KIND) cannot be imported: {ONE_LINE}"
    with pytest.raises(KindRegistryError) as worker:
        worker_kinds()
    assert str(worker.value) == f"job kind broken (broken_kind:KIND) cannot be imported: {ONE_LINE}"
    with pytest.raises(AgentUnavailableError) as agents:  # agents are found through the worker's kinds
        agent_class("oracle", "drag")
    assert str(agents.value) == str(worker.value)


def dist_info(site: Path, name: str, entry_points: str) -> None:
    """A distribution's metadata written into ``site``, as an installer leaves it."""
    info = site / f"{name}-1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {name}\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(entry_points)


def test_a_group_is_read_again_only_when_pythons_path_changed(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    group = "scratchworld_tests.late"
    first = group_entry_points(group)
    assert first == () and group_entry_points(group) is first  # nothing changed: the same reading
    site = tmp_path / "site"
    dist_info(site, "late_one", f"[{group}]\none = late:ONE\n")
    monkeypatch.syspath_prepend(str(site))
    assert [point.name for point in group_entry_points(group)] == ["one"]  # a directory joined the path
    dist_info(site, "late_two", f"[{group}]\ntwo = late:TWO\n")
    assert sorted(point.name for point in group_entry_points(group)) == ["one", "two"]  # installed into it
