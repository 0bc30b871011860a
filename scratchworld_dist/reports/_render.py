"""What every report is drawn from: blocks (headings, paragraphs, tables of text cells, links, code) as Markdown or
as escaped HTML, a self-contained page around HTML, and the formats a report is asked for.

Markdown and HTML are drawn from one list of blocks, so the two always show the same numbers; only the markup
differs. Each kind's report (the episodes' main table, drag's Table 2, perception's, the audit's) and the
diagnosis are drawn this way.
"""

from __future__ import annotations

import html
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

from pydantic import BaseModel

ReportFormat = Literal["md", "html", "json"]
FORMATS: tuple[ReportFormat, ...] = ("md", "html", "json")


@dataclass(frozen=True)
class Heading:
    """A heading of ``level`` (1 is the page title)."""

    level: int
    text: str


@dataclass(frozen=True)
class Paragraph:
    text: str


@dataclass(frozen=True)
class Table:
    """A table of text cells (escaped when drawn, in both markups)."""

    header: list[str]
    rows: list[list[str]]


@dataclass(frozen=True)
class Linked:
    """A paragraph that ends in a link: ``text``, then ``label`` pointing at ``href`` (a relative path we made)."""

    text: str
    label: str
    href: str


@dataclass(frozen=True)
class Code:
    """Preformatted text (pseudocode): a fenced block in Markdown, ``<pre>`` in HTML."""

    text: str


Block = Heading | Paragraph | Linked | Code | Table


def render_text(
    model: BaseModel, markdown: Callable[[], str], fmt: ReportFormat, body: Callable[[], str] | None = None
) -> str:
    """A report in ``fmt``: its Markdown, a page of its HTML ``body`` (default: the Markdown preformatted), or the
    model's JSON."""
    if fmt == "json":
        return model.model_dump_json(indent=2) + "\n"
    if fmt == "html":
        return html_page(body() if body is not None else f"<pre>{html.escape(markdown())}</pre>")
    if fmt == "md":
        return markdown()
    raise ValueError(f"No renderer for format: {fmt}")


def blocks_markdown(blocks: Sequence[Block]) -> str:
    """Headings, paragraphs and tables as Markdown (a report of its own: the text ends with a newline)."""
    parts = []
    for block in blocks:
        if isinstance(block, Heading):
            parts.append(f"{'#' * block.level} {block.text}")
        elif isinstance(block, Paragraph):
            parts.append(block.text)
        elif isinstance(block, Linked):
            parts.append(f"{block.text} [{block.label}](<{block.href}>)")
        elif isinstance(block, Code):
            fence = "`" * max(3, 1 + max((len(run) for run in re.findall(r"`+", block.text)), default=0))
            parts.append(f"{fence}\n{block.text}\n{fence}")
        else:
            lines = [_md_row(block.header), _md_row(["---"] * len(block.header))]
            lines += [_md_row(row) for row in block.rows]
            parts.append("\n".join(lines))
    return "\n\n".join(parts) + "\n"


def html_page(body: str) -> str:
    """A self-contained page (inline style, no external resources) around ``body``, which must be escaped HTML."""
    return _PAGE.format(body=body)


def blocks_html(blocks: Sequence[Block]) -> str:
    """Headings, paragraphs and tables as HTML elements, every string escaped."""
    body = []
    for block in blocks:
        if isinstance(block, Heading):
            body.append(f"<h{block.level}>{html.escape(block.text)}</h{block.level}>")
        elif isinstance(block, Paragraph):
            body.append(f"<p>{html.escape(block.text)}</p>")
        elif isinstance(block, Linked):
            link = f'<a href="{html.escape(block.href)}">{html.escape(block.label)}</a>'
            body.append(f"<p>{html.escape(block.text)} {link}</p>")
        elif isinstance(block, Code):
            body.append(f"<pre>{html.escape(block.text)}</pre>")
        else:
            head = "".join(f"<th>{html.escape(cell)}</th>" for cell in block.header)
            rows = "".join(
                "<tr>" + "".join(f"<td>{html.escape(cell)}</td>" for cell in row) + "</tr>" for row in block.rows
            )
            body.append(f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>")
    return "\n".join(body)


_PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>ScratchWorld report</title>
<style>
body {{ font-family: system-ui, sans-serif; margin: 2em; color: #222; }}
table {{ border-collapse: collapse; margin: 1em 0; }}
th, td {{ border: 1px solid #ccc; padding: 0.3em 0.6em; text-align: right; }}
th:first-child, td:first-child {{ text-align: left; }}
th {{ background: #f3f3f3; }}
</style>
</head>
<body>
{body}
</body>
</html>
"""


def markdown_table(header: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """A Markdown table; a cell's ``|`` is escaped and its line breaks become spaces."""
    return "\n".join(_md_row(line) for line in [header, ["---"] * len(header), *rows])


def _md_row(cells: Sequence[str]) -> str:
    return "| " + " | ".join(c.replace("|", "\\|").replace("\n", " ") for c in cells) + " |"
