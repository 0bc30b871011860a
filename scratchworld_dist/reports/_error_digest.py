"""What went wrong, for the terminal at the end of a run: per error class and model, how many jobs are left in
error and the message most of them ended with (the report counts classes; this says why)."""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Iterable
from pathlib import Path

from pydantic import BaseModel

from scratchworld_dist.results import JobRow, RunStore, effective_rows, require_manifest

MESSAGE_CHARS = 300
"""A message is shown on one line of at most this many characters."""


class ErrorDigest(BaseModel):
    """The jobs of one model left in error of one class, and their most frequent message."""

    error_class: str
    model: str
    jobs: int
    message: str
    """The most frequent message, on one line (ties: the first in sort order)."""

    same: int
    """Jobs whose message is exactly that one."""


def error_digest(rows: Iterable[JobRow]) -> list[ErrorDigest]:
    """Per (class, model) of the jobs whose effective outcome is an error: most jobs first."""
    messages: dict[tuple[str, str], Counter[str]] = defaultdict(Counter)
    for row in effective_rows(list(rows)):
        if row.outcome == "error":
            messages[(row.error_class or "unknown", row.model)][_one_line(row.error_message)] += 1
    digests = []
    for (error_class, model), counts in messages.items():
        message, same = min(counts.items(), key=lambda item: (-item[1], item[0]))
        digests.append(
            ErrorDigest(error_class=error_class, model=model, jobs=sum(counts.values()), message=message, same=same)
        )
    return sorted(digests, key=lambda d: (-d.jobs, d.error_class, d.model))


def run_error_digest(run_dir: Path) -> list[ErrorDigest]:
    """``error_digest`` of a run directory's current rows (rows of an older suite or harness are set aside)."""
    manifest = require_manifest(run_dir)
    return error_digest(manifest.current_rows(RunStore(run_dir).job_rows()))


def digest_lines(digests: list[ErrorDigest]) -> list[str]:
    """The digest as the terminal shows it: a heading, then one line per class and model."""
    if not digests:
        return []
    lines = ["jobs left in error, by class and model, with their most frequent message:"]
    for digest in digests:
        share = f"{digest.same} of {digest.jobs}" if digest.same != digest.jobs else f"all {digest.jobs}"
        lines.append(f"  {digest.error_class} | {digest.model} | {share}: {digest.message}")
    return lines


def _one_line(message: str | None) -> str:
    line = " ".join((message or "(no message)").split())
    return line if len(line) <= MESSAGE_CHARS else line[: MESSAGE_CHARS - 3] + "..."
