"""``perception make``: perception items from any project, with answers from the editor itself.

For each target with scripts, the project is shown in a real editor in its plain view (the scripts framed
as drag tasks frame them, at the default zoom), then in the views of ``_perturb`` (scrolled to cut a script
at the edge, zoomed out; a stack pulled off, a script laid over another, a reporter left beside its slot). Each view's
facts give its candidates (``_candidates``); ``_select`` chooses a balanced set; the views they ask about
are written with their screenshots and saved projects as a suite of our format.

A view whose scripts the editor bumps on loading (so that its screenshot would not come out the same twice)
is left out, as is a target that cannot be selected by name; every omission is reported.
"""

from __future__ import annotations

import random
import re
import tempfile
import time
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import BaseModel

from scratchworld_dist._errors import ProjectFormatError, SuiteError
from scratchworld_dist._files import FileTooLargeError, read_file
from scratchworld_dist.kinds.perception.items._candidates import Candidate, candidates
from scratchworld_dist.kinds.perception.items._item import PerceptionItem, PerceptionView
from scratchworld_dist.kinds.perception.items._native import write_perception_suite
from scratchworld_dist.kinds.perception.items._page import Look, lending_pool, look
from scratchworld_dist.kinds.perception.items._perturb import bumped, cut_view, perturbations, zoom_view
from scratchworld_dist.kinds.perception.items._select import select
from scratchworld_dist.sb3 import Sb3Archive, check_project
from scratchworld_dist.sb3.editing import frame_view
from workers.contract import MIB, BridgeError, DragView, EditorError, ProjectLimits
from workers.editor import Editor, EditorPool

DEFAULT_PER_VIEW = 8
CUT_CHANGE = "the view scrolled so that the workspace's right edge cuts through the widest script"
ZOOM_CHANGE = "the view zoomed out until the blocks' words are too small to read"


class MadeSuite(BaseModel):
    """What ``make_perception_suite`` wrote, what it left out, and what it cost."""

    root: Path
    items: int
    views: int
    views_shown: int
    candidates: int
    seconds: float
    composition: dict[str, int]
    """Items by ``kind/tag/answer`` (answer: YES, NO or value)."""

    problems: list[str]


@dataclass(frozen=True)
class _Project:
    label: str
    path: Path
    data: bytes
    json: dict[str, Any]


@dataclass(frozen=True)
class _Shown:
    kind: str
    """plain, cut, zoom_out, or the perturbation's kind."""

    view: PerceptionView
    candidates: list[Candidate]


def read_projects(paths: Sequence[Path]) -> list[_Project]:
    """The projects named, checked as a worker checks them; ``SuiteError`` names the first that is unusable."""
    limits = ProjectLimits()
    stems = [path.stem for path in paths]
    found = []
    for path in paths:
        try:
            data = read_file(path, int(limits.max_file_mb * MIB))
            project = check_project(data, limits)
        except FileTooLargeError as exc:
            raise SuiteError(f"the project is {exc.strerror}, over project_limits.max_file_mb", path) from None
        except ProjectFormatError as exc:
            raise SuiteError(f"not a usable Scratch 3 project: {exc}", path) from None
        except OSError as exc:
            raise SuiteError(f"cannot read: {exc.strerror or exc}", path) from None
        # Projects named alike (each task's initial.sb3) are told apart by their folder.
        label = path.stem if stems.count(path.stem) == 1 else f"{path.parent.name}-{path.stem}"
        found.append(_Project(_slug(label), path, data, project))
    labels = Counter(project.label for project in found)
    if twice := sorted(label for label, count in labels.items() if count > 1):
        raise SuiteError(f"two projects would share the name {twice[0]!r}: rename one", paths[0])
    return found


def check_destination(out: Path) -> None:
    """Refuse, before any work, a destination that holds files."""
    if out.exists() and (not out.is_dir() or any(out.iterdir())):
        raise SuiteError("refusing to write a perception suite into a folder that is not empty", out)


async def make_perception_suite(
    paths: Sequence[Path],
    out: Path,
    *,
    name: str,
    per_view: int = DEFAULT_PER_VIEW,
    max_views: int | None = None,
    seed: int = 0,
    on_problem: Callable[[str], None] = lambda _: None,
    on_view: Callable[[PerceptionView, int], None] = lambda _view, _count: None,
    pool: EditorPool | None = None,
) -> MadeSuite:
    """Make, select and write the items of ``paths`` as a suite at ``out`` (a new or empty folder).

    At most ``per_view`` items ask about one view, and at most ``max_views`` views (default: all) are used.
    Editors come from ``pool`` when given, else from a browser of its own. Raises ``SuiteError``, writing
    nothing, when no item comes of them (before a browser starts when no project has a script to show).
    """
    check_destination(out)
    projects = read_projects(paths)
    started = time.perf_counter()
    problems: list[str] = []

    def problem(message: str) -> None:
        problems.append(message)
        on_problem(message)

    targets = [(project, _targets(project, problem)) for project in projects]
    if not any(found for _, found in targets):
        raise SuiteError(f"no perception item made: none of the {len(projects)} project(s) has a script to show")
    shown: list[_Shown] = []
    with tempfile.TemporaryDirectory(prefix="scratchworld-perception-") as scratch:
        folder = Path(scratch)
        async with lending_pool(pool) as lender:
            for project, found in targets:
                # One editor shows a project's views; a page that died takes only its project's views along.
                async with lender.editor() as editor:
                    for index, sprite, slug in found:
                        views = await _target_views(editor, project, index, sprite, slug, folder, seed, problem)
                        for view in views:
                            on_view(view.view, len(view.candidates))
                        shown += views
        used = choose_views(shown, max_views, seed)
        chosen = select({s.view.id: s.candidates for s in used}, per_view=per_view, seed=seed)
        views = [s.view for s in shown if s.view.id in chosen]
        items = [item for view in views for item in _items(view, chosen[view.id])]
        if not items:
            raise SuiteError(
                f"no perception item made: none of the {len(shown)} view(s) shown settles a question beyond doubt"
            )
        write_perception_suite(items, views, out, name)
    composition = Counter(f"{i.kind}/{i.tag}/{i.answer if i.answer_format == 'yes_no' else 'value'}" for i in items)
    return MadeSuite(
        root=out, items=len(items), views=len(views), views_shown=len(shown),
        candidates=sum(len(s.candidates) for s in shown), seconds=time.perf_counter() - started,
        composition=dict(sorted(composition.items())), problems=problems,
    )  # fmt: skip


VIEW_PRIORITY = ("pull_off", "cover", "beside_slot", "cut", "zoom_out", "plain")
"""The order in which view kinds take turns when views are capped: the perturbed views hold the hard cases."""


def choose_views(shown: Sequence[_Shown], max_views: int | None, seed: int) -> list[_Shown]:
    """At most ``max_views`` of the views (with candidates): kinds take turns in ``VIEW_PRIORITY`` order,
    each kind's views in a seeded order; the views keep the order in which they were made."""
    usable = [s for s in shown if s.candidates]
    if max_views is None or len(usable) <= max_views:
        return usable
    queues = {kind: [s for s in usable if s.kind == kind] for kind in VIEW_PRIORITY}
    for kind, queue in queues.items():
        random.Random(f"{seed}:{kind}").shuffle(queue)
    picked: set[str] = set()
    while len(picked) < max_views:
        for queue in queues.values():
            if queue and len(picked) < max_views:
                picked.add(queue.pop().view.id)
    return [s for s in usable if s.view.id in picked]


def _targets(project: _Project, problem: Callable[[str], None]) -> list[tuple[int, str | None, str]]:
    """(index, sprite name or None for the Stage, slug) of the targets with scripts that a view can select."""
    targets = [t for t in project.json.get("targets", []) if isinstance(t, dict)]
    names = Counter(t.get("name") for t in targets if not t.get("isStage"))
    found: list[tuple[int, str | None, str]] = []
    slugs: set[str] = set()
    for index, target in enumerate(project.json.get("targets", [])):
        if not isinstance(target, dict) or not _has_scripts(target):
            continue
        name = target.get("name")
        if not target.get("isStage") and (not isinstance(name, str) or not name or names[name] > 1):
            problem(f"{project.label}: a sprite named {name!r} cannot be selected by name; left out")
            continue
        slug = "stage" if target.get("isStage") else _slug(str(name))
        while slug in slugs:
            slug += "_"
        slugs.add(slug)
        found.append((index, None if target.get("isStage") else str(name), slug))
    return found


def _has_scripts(target: dict[str, Any]) -> bool:
    blocks = target.get("blocks")
    return isinstance(blocks, dict) and bool(_tops(blocks))


async def _target_views(
    editor: Editor,
    project: _Project,
    index: int,
    sprite: str | None,
    slug: str,
    folder: Path,
    seed: int,
    problem: Callable[[str], None],
) -> list[_Shown]:
    """The plain view of one target, its cut and zoomed-out views and its perturbed views, each shown and measured."""
    base = f"{project.label}-{slug}"
    blocks: dict[str, Any] = project.json["targets"][index]["blocks"]
    rng = random.Random(f"{seed}:{base}")
    archive = Sb3Archive(project.data)
    try:
        plain = await _view(editor, project.data, sprite, blocks)
        seen = await look(editor, project.data, plain, base)
    except (EditorError, BridgeError) as exc:
        problem(f"{base}: cannot be shown: {exc}")
        return []
    if moved := bumped(blocks, seen.facts):
        problem(f"{base}: the editor moved {len(moved)} script(s) on loading it; left out")
        return []
    shown = [_keep(folder, base, "plain", project, project.data, plain, seen, "", seed)]
    for kind, other, change in (
        ("cut", cut_view(plain, seen.facts), CUT_CHANGE),
        ("zoom_out", zoom_view(plain, seen.facts), ZOOM_CHANGE),
    ):
        try:
            if other is not None:
                again = await look(editor, project.data, other, base)
                shown.append(_keep(folder, base, kind, project, project.data, other, again, change, seed))
        except (EditorError, BridgeError) as exc:
            problem(f"{base}: the {kind} view cannot be shown: {exc}")
    for change in perturbations(blocks, seen.facts, rng):
        for attempt in change.attempts:
            data = archive.with_project(_with_blocks(project.json, index, attempt))
            try:
                view = await _view(editor, data, sprite, attempt)
                changed = await look(editor, data, view, base)
            except (EditorError, BridgeError) as exc:
                problem(f"{base}: the {change.kind} view cannot be shown: {exc}")
                break
            if not bumped(attempt, changed.facts):
                shown.append(_keep(folder, base, change.kind, project, data, view, changed, change.change, seed))
                break
        else:
            problem(f"{base}: every placement of the {change.kind} change is bumped by the editor; left out")
    return shown


async def _view(editor: Editor, data: bytes, sprite: str | None, blocks: dict[str, Any]) -> DragView:
    view, _ = await frame_view(editor, data, sprite, _tops(blocks))
    return view


def _keep(
    folder: Path,
    base: str,
    kind: str,
    project: _Project,
    data: bytes,
    view: DragView,
    seen: Look,
    change: str,
    seed: int,
) -> _Shown:
    """The view saved under ``folder`` (project and screenshot) with its candidates."""
    view_id = f"{base}-{kind}"
    (folder / f"{view_id}.sb3").write_bytes(data)
    (folder / f"{view_id}.png").write_bytes(seen.png)
    source = f"{project.path.parent.name}/{project.path.name}" if project.path.parent.name else project.path.name
    record = PerceptionView(
        id=view_id, project=folder / f"{view_id}.sb3", view=view, screenshot=folder / f"{view_id}.png",
        source=source, change=change,
    )  # fmt: skip
    return _Shown(kind, record, candidates(seen.facts, random.Random(f"{seed}:{view_id}")))


def _with_blocks(project: dict[str, Any], index: int, blocks: dict[str, Any]) -> dict[str, Any]:
    targets = list(project["targets"])
    targets[index] = {**targets[index], "blocks": blocks}
    return {**project, "targets": targets}


def _items(view: PerceptionView, chosen: Sequence[Candidate]) -> list[PerceptionItem]:
    numbers: Counter[str] = Counter()
    items = []
    for candidate in chosen:
        number = numbers[candidate.kind]
        numbers[candidate.kind] += 1
        derived = candidate.derived
        items.append(
            PerceptionItem(
                id=f"{view.id}-{candidate.kind}-{number}", kind=candidate.kind, tag=derived.tag,
                question=candidate.question, answer_format="yes_no" if derived.value_kind is None else "value",
                value_kind=derived.value_kind, answer=derived.answer, screenshot=view.screenshot, view=view.id,
                fact=candidate.fact,
            )
        )  # fmt: skip
    return items


def _tops(blocks: dict[str, Any]) -> list[str]:
    """The ids of a target's scripts (a top-level shadow, which some saved projects hold, draws nothing)."""
    return [key for key, b in blocks.items() if isinstance(b, dict) and b.get("topLevel") and not b.get("shadow")]


def _slug(text: str) -> str:
    """A plain name of at most 48 characters: a view id (project, target, kind) and an item id stay under 128."""
    return re.sub(r"[^A-Za-z0-9._-]+", "_", text).strip("._-")[:48] or "project"
