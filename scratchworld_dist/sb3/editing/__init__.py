"""Editing Scratch projects for generated benchmarks: what drag tasks and perception views both do to a project.

Detaching blocks from a script (``detach``, ``cut_link``), naming blocks as the editor shows them
(``block_label``, ``template_parts``...), and framing a view of them in a real editor (``frame_view``). The
framing needs the browser stack, so it is imported on first use: importing this package stays light.
"""

import typing

import workers
from scratchworld_dist.sb3.editing._detach import (
    COMPACT_REPORTERS,
    FAR,
    ROW_Y,
    SHIFT_X,
    ScriptLink,
    cut_link,
    detach,
    stack_tail,
)
from scratchworld_dist.sb3.editing._labels import (
    Part,
    block_label,
    is_boolean,
    offered_in_palette,
    palette_label,
    palette_offers,
    slot_phrase,
    template_parts,
    templated_opcodes,
)

if typing.TYPE_CHECKING:
    from scratchworld_dist.sb3.editing._frame import DEFAULT_SCALE, PaletteBlock, frame_view

__getattr__ = workers.lazy_exports(__name__, {"._frame": ("DEFAULT_SCALE", "PaletteBlock", "frame_view")})

__all__ = [
    "COMPACT_REPORTERS",
    "DEFAULT_SCALE",
    "FAR",
    "ROW_Y",
    "SHIFT_X",
    "PaletteBlock",
    "Part",
    "ScriptLink",
    "block_label",
    "cut_link",
    "detach",
    "frame_view",
    "is_boolean",
    "offered_in_palette",
    "palette_label",
    "palette_offers",
    "slot_phrase",
    "stack_tail",
    "template_parts",
    "templated_opcodes",
]
