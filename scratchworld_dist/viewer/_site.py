"""The viewer as a set of relative paths: the one map both the local server and the static export use.

::

    index.html                      the runs, and comparisons between them
    static/<file>                   the stylesheet and the jobs table's script (shipped in the package)
    runs/<k>/index.html             run k: the report's tables and plots, errors by class, the manifest
    runs/<k>/jobs.html              its jobs: filter, sort, search (data in jobs-data.js, a script, so
    runs/<k>/jobs-data.js           that it loads from file:// too)
    runs/<k>/jobs/<job_id>.html     one job: header, attempts, tests, steps, final project
    runs/<k>/files/<path>           the run's artifacts (screenshots, final.sb3)
    runs/<k>/images/<sha256>.png    images the run keeps once for many jobs (perception screenshots)
    compare/<a>-<b>.html            run a against run b, of one kind that compares runs (episodes)
    compare/<k>-<name>.html         a comparison within run k its kind offers (the episodes' gap: composite vs
                                    primitive)
"""

from __future__ import annotations

import json
import mimetypes
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path

from scratchworld_dist._errors import RunDirError
from scratchworld_dist.results import local_folder
from scratchworld_dist.viewer._html import STATIC_FILES, render_page, static_file
from scratchworld_dist.viewer._pages import job_page, jobs_data, run_card, run_page
from scratchworld_dist.viewer._runs import ARTIFACTS, ViewedRun
from scratchworld_dist.viewer._timeline import PAGE_SIZE

MAX_PAIRWISE = 6
"""Runs up to which the runs page offers every pair's comparison (more would be a long list)."""

FILTERS = ("model", "mode", "agent", "category", "task_id", "seed", "setting", "outcome", "error_class")
HEADERS = (
    ("task_id", "task"),
    ("category", "category"),
    ("mode", "mode"),
    ("agent", "agent"),
    ("model", "model"),
    ("seed", "seed"),
    ("outcome", "outcome"),
    ("error_class", "error class"),
    ("tests_passed", "tests"),
    ("steps", "steps"),
    ("cost_usd", "cost"),
    ("episode_s", "time (s)"),
    ("attempts", "attempts"),
)
_JOB_ID = re.compile(r"[A-Za-z0-9_-]{1,128}")
_COMPARE = re.compile(r"(\d+)-(\d+|[a-z_]+)\.html")


@dataclass(frozen=True)
class Resource:
    """What a path serves: bytes built now, or a file of a run directory."""

    content_type: str
    body: bytes | None = None
    file: Path | None = None


class ViewerSite:
    """The pages of one or more run directories."""

    def __init__(self, run_dirs: Sequence[Path]) -> None:
        if not run_dirs:
            raise RunDirError("no run directory given")
        unique: dict[Path, Path] = {}
        for path in run_dirs:
            unique.setdefault(path.resolve(), path)
        self.runs = [ViewedRun(path) for path in unique.values()]
        self._plots_cache: dict[Path, tuple[object, str]] = {}

    def get(self, path: str) -> Resource | None:
        """The resource at ``path`` (relative, ``/``-separated), or None when there is none."""
        parts = [p for p in path.strip("/").split("/") if p]
        if not parts or parts == ["index.html"]:
            return _html(self._index())
        if parts[0] == "static" and len(parts) == 2:
            body = static_file(parts[1])
            return None if body is None else Resource(_type(parts[1]), body=body)
        if parts[0] == "compare" and len(parts) == 2 and (match := _COMPARE.fullmatch(parts[1])):
            return self._compare(int(match[1]), match[2])
        if parts[0] == "runs" and len(parts) >= 3 and parts[1].isdigit() and int(parts[1]) < len(self.runs):
            return self._run_resource(int(parts[1]), parts[2:])
        return None

    def page_paths(self) -> Iterator[str]:
        """Every page and script of the site (its artifacts are ``artifact_files``)."""
        yield "index.html"
        yield from (f"static/{name}" for name in STATIC_FILES)
        for k, run in enumerate(self.runs):
            yield from (f"runs/{k}/index.html", f"runs/{k}/jobs.html", f"runs/{k}/jobs-data.js")
            yield from (f"runs/{k}/jobs/{job}.html" for job in sorted({r.job_id for r in run.rows()}))
        yield from (href for href, _ in self._comparisons())

    def artifact_files(self) -> Iterator[tuple[str, Path]]:
        """(site path, file) of every artifact the jobs' pages link to."""
        for k, run in enumerate(self.runs):
            root = (run.path / ARTIFACTS).resolve()  # the run may be reached through a symlink
            for row in run.rows():
                if row.artifact_dir is None:
                    continue
                folder = local_folder(run.path, row.artifact_dir).resolve()
                if not folder.is_relative_to(root) or not folder.is_dir():
                    continue
                for file in sorted(folder.rglob("*")):
                    if file.is_file() and file.name != "trajectory.jsonl":
                        yield f"runs/{k}/files/{file.relative_to(root).as_posix()}", file
            for image in run.shared_images():
                yield f"runs/{k}/images/{image.name}", image

    def _run_resource(self, k: int, rest: list[str]) -> Resource | None:
        run = self.runs[k]
        if rest == ["index.html"]:
            return _html(render_page("run.html", "../../", page=run_page(k, run, self._plots(run))))
        if rest == ["jobs.html"]:
            page = render_page("jobs.html", "../../", run=run_card(k, run), filters=FILTERS, headers=HEADERS)
            return _html(page)
        if rest == ["jobs-data.js"]:
            # Plain JSON is a script; "<" escaped so no text in it can ever read as markup.
            data = json.dumps(jobs_data(run).model_dump(), separators=(",", ":"), ensure_ascii=True).replace(
                "<", "\\u003c"
            )
            return Resource("text/javascript; charset=utf-8", body=f"window.scratchworldJobs = {data};\n".encode())
        if rest[0] == "jobs" and len(rest) == 2 and (job := rest[1].removesuffix(".html")) and _JOB_ID.fullmatch(job):
            page = job_page(k, run, job)
            return None if page is None else _html(render_page("job.html", "../../../", page=page, page_size=PAGE_SIZE))
        if rest[0] == "files" and len(rest) > 1:
            file = run.artifact("/".join(rest[1:]))
            return None if file is None else Resource(_type(file.name), file=file)
        if rest[0] == "images" and len(rest) == 2:
            image = run.shared_image(rest[1])
            return None if image is None else Resource("image/png", file=image)
        return None

    def _plots(self, run: ViewedRun) -> str:
        """The run's plots, drawn again only when its results changed (drawing is most of a run page's time)."""
        version = run.version()
        cached = self._plots_cache.get(run.path)
        if cached is not None and cached[0] == version:
            return cached[1]
        drawn = run.kind().plots_html(run.rows())  # the rows the page read already, not the shards again
        self._plots_cache[run.path] = (version, drawn)
        return drawn

    def _index(self) -> bytes:
        cards = [run_card(k, run) for k, run in enumerate(self.runs)]
        comparisons = [{"href": href, "title": title} for href, title in self._comparisons()]
        return render_page("index.html", "", runs=cards, comparisons=comparisons)

    def _comparisons(self) -> list[tuple[str, str]]:
        found = []
        names = [f"{k}: {run.path.name}" for k, run in enumerate(self.runs)]
        kinds = [run.kind() for run in self.runs]
        if len(self.runs) <= MAX_PAIRWISE:
            for a in range(len(self.runs)):
                found += [
                    (f"compare/{a}-{b}.html", f"{names[a]} vs {names[b]}")
                    for b in range(a + 1, len(self.runs))
                    if kinds[a].compares_runs and kinds[b] is kinds[a]
                ]
        for k, run in enumerate(self.runs):
            for view in kinds[k].run_comparisons(run.effective_rows()):
                note = f" ({view.note})" if view.note else ""
                found.append((f"compare/{k}-{view.name}.html", f"{names[k]}: {view.title}{note}"))
        return found

    def _compare(self, a: int, other: str) -> Resource | None:
        if a >= len(self.runs) or (other.isdigit() and int(other) >= len(self.runs)):
            return None
        kind, path = self.runs[a].kind(), self.runs[a].path
        if other.isdigit():
            b = self.runs[int(other)].path
            if not kind.compares_runs or self.runs[int(other)].kind() is not kind:
                return None
            title, make = f"{path.name} vs {b.name}", lambda: kind.comparison_html(path, b)
        else:
            view = next((v for v in kind.run_comparisons(self.runs[a].effective_rows()) if v.name == other), None)
            if view is None:
                return None
            title, make = f"{path.name}: {view.title}", lambda: kind.run_comparison_html(path, other)
        try:
            body, error = make(), None
        except RunDirError as exc:
            body, error = None, str(exc)
        return _html(render_page("compare.html", "../", title=title, body=body, error=error))


def _html(body: bytes) -> Resource:
    return Resource("text/html; charset=utf-8", body=body)


def _type(name: str) -> str:
    if name.endswith(".js"):
        return "text/javascript; charset=utf-8"
    if name.endswith(".css"):
        return "text/css; charset=utf-8"
    return mimetypes.guess_type(name)[0] or "application/octet-stream"
