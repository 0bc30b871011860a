"""`drag make` and `perception make` given projects that yield nothing: a non-zero exit, a one-line reason, and
no suite folder written (an empty suite would look like a made one). Each case fails before a browser starts."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from scratchworld_dist.sb3 import Project, Sb3Archive, block, circle_costume
from tests.support.cli_runner import invoke


def _unusable(tmp: Path) -> Path:
    path = tmp / "notes.sb3"
    path.write_text("hello, I am a text file")
    return path


def _scriptless(tmp: Path) -> Path:
    """A project that loads: one sprite, a costume, no scripts."""
    project = Project()
    project.sprite("Dot", costume=circle_costume("dot", 10, "#36c"))
    path = tmp / "still.sb3"
    path.write_bytes(project.to_sb3())
    return path


def _twins(tmp: Path) -> Path:
    """Scripts only on two sprites named alike: no view can select either."""
    project = Project()
    for name in ("Twin", "Other"):
        project.sprite(name, costume=circle_costume("dot", 10, "#36c")).script(
            block("event_whenflagclicked"), block("looks_say", MESSAGE="hi")
        )
    data = project.to_sb3()
    renamed = project.to_project_json()
    for target in renamed["targets"]:
        if target.get("name") == "Other":
            target["name"] = "Twin"
    path = tmp / "twins.sb3"
    path.write_bytes(Sb3Archive(data).with_project(renamed))
    return path


@pytest.mark.parametrize(
    ("build", "reason"),
    [
        (_unusable, "none of the 1 project(s) gives a candidate (1 problem(s) reported)"),
        (_scriptless, "hold no script with a connection to detach"),
    ],
)
def test_drag_make_that_makes_no_task_fails_and_writes_nothing(
    tmp_path: Path, build: Callable[[Path], Path], reason: str
) -> None:
    out = tmp_path / "out"
    done = invoke("drag", "make", str(build(tmp_path)), "--out", str(out))
    assert done.returncode == 2, done
    assert "error: no drag task made: " in done.stderr and reason in done.stderr
    assert "wrote" not in done.stdout + done.stderr
    assert not out.exists()


def test_drag_make_names_each_unusable_project_left_out(tmp_path: Path) -> None:
    bad = _unusable(tmp_path)
    done = invoke("drag", "make", str(bad), str(_scriptless(tmp_path)), "--out", str(tmp_path / "out"))
    assert done.returncode == 2
    assert "left out: notes: not a usable project" in done.stderr
    assert "none of the 2 project(s) gives a candidate" in done.stderr


@pytest.mark.parametrize(
    ("build", "left_out"),
    [(_scriptless, None), (_twins, "a sprite named 'Twin' cannot be selected by name")],
)
def test_perception_make_that_has_nothing_to_show_fails_and_writes_nothing(
    tmp_path: Path, build: Callable[[Path], Path], left_out: str | None
) -> None:
    out = tmp_path / "out"
    done = invoke("perception", "make", str(build(tmp_path)), "--out", str(out))
    assert done.returncode == 2, done
    assert "error: no perception item made: none of the 1 project(s) has a script to show" in done.stderr
    if left_out is not None:
        assert left_out in done.stderr
    assert "wrote" not in done.stdout + done.stderr
    assert not out.exists()
