"""Reading and building Scratch 3 project files (.sb3)."""

from scratchworld_dist.sb3._builder import (
    Block,
    Costume,
    Project,
    Target,
    backdrop_costume,
    block,
    circle_costume,
    list_contents,
    rect_costume,
    variable,
)
from scratchworld_dist.sb3._catalog import SHAPES
from scratchworld_dist.sb3._listing import ListedLine, script_lines, script_listing, target_listing
from workers.contract import Sb3Archive, check_project

__all__ = [
    "SHAPES",
    "Block",
    "Costume",
    "ListedLine",
    "Project",
    "Sb3Archive",
    "Target",
    "backdrop_costume",
    "block",
    "check_project",
    "circle_costume",
    "list_contents",
    "rect_costume",
    "script_lines",
    "script_listing",
    "target_listing",
    "variable",
]
