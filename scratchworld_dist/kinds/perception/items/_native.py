"""Our own perception-suite format, read by ``load_perception_suite`` and written by ``write_perception_suite``.

::

    SUITE/perception-suite.json   {"format": "scratchworld_dist/perception/1", "name": ..., "items": N, "views": M}
    SUITE/items.jsonl             one PerceptionItem per line; paths relative to SUITE
    SUITE/views.jsonl             one PerceptionView per line (the screenshots' projects and editor views)
    SUITE/screenshots/<view>.png  what the questions are about
    SUITE/projects/<view>.sb3     the projects as shown (a view's perturbations saved in)

JSON lines keep a few hundred items in two files that diff line by line. An item or view that does not
validate, names a file outside the suite or a view that is not there is left out with a problem naming
its line. The manifest is written last, so a folder whose writing was interrupted is not mistaken for a
suite, and its counts say how many lines there should be.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Literal, TypeVar

from pydantic import BaseModel, ConfigDict, Field, ValidationError

from scratchworld_dist._errors import SuiteError, validation_summary
from scratchworld_dist._files import MAX_TEXT_BYTES, read_file, read_text, write_atomic
from scratchworld_dist.kinds.perception.items._item import PerceptionItem, PerceptionView
from scratchworld_dist.kinds.perception.items._suite import PerceptionSuite
from scratchworld_dist.suites import SuiteKind, SuiteProblem, SuiteProblems

SUITE_FILE = "perception-suite.json"
ITEMS_FILE = "items.jsonl"
VIEWS_FILE = "views.jsonl"
FORMAT = "scratchworld_dist/perception/1"
MAX_SCREENSHOT_BYTES = 16 * 1024 * 1024
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"

RecordT = TypeVar("RecordT", PerceptionItem, PerceptionView)


class PerceptionSuiteFile(BaseModel):
    """perception-suite.json."""

    model_config = ConfigDict(extra="forbid")

    format: Literal["scratchworld_dist/perception/1"]
    name: str = Field(min_length=1, pattern=r"^[^\x00-\x1f\x7f]*$")
    """Shown in every message and report: no line breaks or escape sequences."""

    items: int = Field(ge=0)
    views: int = Field(ge=0)


class NativePerceptionLoader:
    """Loads a folder holding ``perception-suite.json``."""

    kind: SuiteKind = "scratchworld_dist"

    @staticmethod
    def handles(root: Path) -> bool:
        return (root / SUITE_FILE).is_file()

    def load(self, root: Path) -> PerceptionSuite:
        reader = SuiteProblems(root)
        manifest = reader.read_model(root / SUITE_FILE, PerceptionSuiteFile)
        reader.raise_if_any()  # without the manifest there is no suite
        assert manifest is not None
        problems: list[SuiteProblem] = []
        views = _records(root, VIEWS_FILE, PerceptionView, manifest.views, problems)
        kept_views: dict[str, PerceptionView] = {}
        for line, view in views:
            where = root / f"{VIEWS_FILE}:{line}"
            bad = _outside(root, view.project) or _outside(root, view.screenshot)
            if bad is not None or view.id in kept_views:
                problems.append(SuiteProblem(path=where, message=bad or f"view {view.id!r} is listed twice"))
                continue
            kept_views[view.id] = view.model_copy(
                update={"project": root / view.project, "screenshot": root / view.screenshot}
            )
        items: list[PerceptionItem] = []
        seen: set[str] = set()
        for line, item in _records(root, ITEMS_FILE, PerceptionItem, manifest.items, problems):
            where = root / f"{ITEMS_FILE}:{line}"
            bad = _outside(root, item.screenshot)
            if bad is None and item.id in seen:
                bad = f"item {item.id!r} is listed twice"
            if bad is None and item.view is not None and item.view not in kept_views:
                bad = f"view: {item.view!r} is not a view of the suite"
            if bad is not None:
                problems.append(SuiteProblem(path=where, message=bad))
                continue
            seen.add(item.id)
            items.append(item.model_copy(update={"screenshot": root / item.screenshot}))
        return PerceptionSuite(
            name=manifest.name, kind="scratchworld_dist", root=root, items=tuple(items),
            views=tuple(kept_views.values()), problems=tuple(problems),
        )  # fmt: skip


def _records(
    root: Path, name: str, model: type[RecordT], expected: int, problems: list[SuiteProblem]
) -> list[tuple[int, RecordT]]:
    """The valid lines of a JSON-lines file, by line number; every bad line (and a wrong count) a problem."""
    path = root / name
    try:
        text = read_text(path, MAX_TEXT_BYTES)
    except FileNotFoundError:
        problems.append(SuiteProblem(path=path, message="missing"))
        return []
    except (OSError, UnicodeDecodeError) as exc:
        problems.append(SuiteProblem(path=path, message=f"cannot read: {exc}"))
        return []
    records: list[tuple[int, RecordT]] = []
    lines = [(number, line) for number, line in enumerate(text.splitlines(), start=1) if line.strip()]
    for number, line in lines:
        try:
            records.append((number, model.model_validate_json(line)))
        except ValidationError as exc:
            problems.append(SuiteProblem(path=root / f"{name}:{number}", message=validation_summary(exc)))
    if len(lines) != expected:
        message = f"holds {len(lines)} line(s); {SUITE_FILE} says {expected}"
        problems.append(SuiteProblem(path=path, message=message))
    return records


def _outside(root: Path, path: Path) -> str | None:
    """Why ``path`` (relative to ``root``) cannot be used, or None."""
    if path.is_absolute() or ".." in path.parts:
        return f"{str(path)!r} is outside the suite folder"
    if not (root / path).is_file():
        return f"{str(path)!r} does not exist in the suite folder"
    return None


def read_screenshot(path: Path) -> bytes:
    """A screenshot's bytes, checked to be a PNG of reasonable size (``SuiteError`` names the file)."""
    try:
        data = read_file(path, MAX_SCREENSHOT_BYTES)
    except OSError as exc:
        raise SuiteError(f"cannot read the screenshot: {exc.strerror or exc}", path) from exc
    if not data.startswith(PNG_SIGNATURE):
        raise SuiteError("the screenshot is not a PNG image", path)
    return data


def write_perception_suite(
    items: Sequence[PerceptionItem], views: Sequence[PerceptionView], dest: Path, name: str
) -> Path:
    """Write ``items`` (about ``views``) as a suite of our format at ``dest``, a new or empty folder.

    Each view's screenshot and project (any readable paths) are copied in as ``screenshots/<view>.png`` and
    ``projects/<view>.sb3``; an item of a view shows its view's screenshot, an item without one (a question
    written by hand about any screenshot) has its own copied in by content (``screenshots/<sha256>.png``, once).
    Raises ``SuiteError`` before writing anything when ids clash, an item names a view that is not given, or
    ``dest`` holds files.
    """
    dest = Path(dest)
    try:
        manifest = PerceptionSuiteFile(format=FORMAT, name=name, items=len(items), views=len(views))
    except ValidationError as exc:
        raise SuiteError(f"cannot name a perception suite {name[:80]!r}: {validation_summary(exc)}", dest) from None
    if dest.exists() and (not dest.is_dir() or any(dest.iterdir())):
        raise SuiteError("refusing to write a perception suite into a folder that is not empty", dest)
    _distinct("item", (item.id for item in items), dest)
    _distinct("view", (view.id for view in views), dest)
    by_id = {view.id: view for view in views}
    for item in items:
        if item.view is not None and item.view not in by_id:
            raise SuiteError(f"item {item.id} names view {item.view!r}, which is not among the views", dest)
    (dest / "screenshots").mkdir(parents=True, exist_ok=True)
    written: list[PerceptionView] = []
    for view in views:
        shot, project = Path("screenshots") / f"{view.id}.png", Path("projects") / f"{view.id}.sb3"
        (dest / "projects").mkdir(exist_ok=True)
        write_atomic(dest / shot, read_screenshot(view.screenshot), sync=False)
        write_atomic(dest / project, read_file(view.project, MAX_SCREENSHOT_BYTES * 4), sync=False)
        written.append(view.model_copy(update={"screenshot": shot, "project": project}))
    shots = {view.id: view.screenshot for view in written}
    lines: list[PerceptionItem] = []
    for item in items:
        if item.view is not None:
            lines.append(item.model_copy(update={"screenshot": shots[item.view]}))
            continue
        data = read_screenshot(item.screenshot)
        shot = Path("screenshots") / f"{hashlib.sha256(data).hexdigest()}.png"
        if not (dest / shot).is_file():
            write_atomic(dest / shot, data, sync=False)
        lines.append(item.model_copy(update={"screenshot": shot}))
    _write_lines(dest / VIEWS_FILE, written, exclude_none=False)
    _write_lines(dest / ITEMS_FILE, lines)
    write_atomic(dest / SUITE_FILE, (manifest.model_dump_json(indent=2) + "\n").encode("utf-8"), sync=False)
    return dest


def _distinct(what: str, ids: Iterable[str], dest: Path) -> None:
    listed = list(ids)
    twice = sorted({i for i in listed if listed.count(i) > 1})
    if twice:
        raise SuiteError(f"two {what}s share an id: {', '.join(twice[:10])}", dest)


def _write_lines(path: Path, records: Sequence[BaseModel], *, exclude_none: bool = True) -> None:
    """One record a line; ``exclude_none`` leaves out unset optional fields (not for records where None means
    something, such as a view's ``sprite``: None is the Stage)."""
    text = "".join(json.dumps(record.model_dump(mode="json", exclude_none=exclude_none)) + "\n" for record in records)
    write_atomic(path, text.encode("utf-8"), sync=False)
