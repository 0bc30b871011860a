"""Checking a drag task against its project, before any browser sees it.

Two kinds of findings: the task's blocks are not the project's (the task cannot be judged, so it
is skipped), or the view does not show them (the task is kept, without a view). Messages name the
field of the file being read, which differs between our format and upstream's.
"""

from __future__ import annotations

from dataclasses import dataclass

from scratchworld_dist.kinds.drag.items._project import ProjectIndex, palette_category_of
from workers.contract import DragView
from workers.kinds.drag import CanvasSource, DragSource, FlyoutSource


@dataclass(frozen=True)
class FieldNames:
    """What a file of one format calls each checked field."""

    reference: str
    reference_opcode: str
    source: str
    source_opcode: str
    tail: str
    target: str
    category: str


OUR_FIELDS = FieldNames(
    reference="reference_block_id",
    reference_opcode="reference_opcode",
    source="source.block_id",
    source_opcode="source.opcode",
    tail="source.tail_block_id",
    target="view.sprite",
    category="view.category",
)

UPSTREAM_FIELDS = FieldNames(
    reference="evaluation_config.reference_block_id",
    reference_opcode="evaluation_config.reference_block_opcode",
    source="evaluation_config.target_block_id",
    source_opcode="evaluation_config.target_block_opcode",
    tail="evaluation_config.target_stack_tail_block_id",
    target="evaluation_config.switch_sprite_actions",
    category="evaluation_config.locate_target_actions",
)


def block_problems(
    project: ProjectIndex, source: DragSource, reference_id: str, reference_opcode: str, names: FieldNames
) -> list[str]:
    """Why the task's blocks are not the project's (one line each), or nothing."""
    problems = _block(project, reference_id, reference_opcode, names.reference, names.reference_opcode)
    if isinstance(source, CanvasSource):
        problems += _block(project, source.block_id, source.opcode, names.source, names.source_opcode)
        if source.block_id == reference_id:
            problems.append(f"{names.source}: the source is the reference block itself")
        elif not problems and (tail := project.stack_tail(source.block_id)) != source.tail_block_id:
            problems.append(f"{names.tail}: {source.tail_block_id!r}, but the source's stack ends at {tail!r}")
    return problems


def view_problems(
    project: ProjectIndex, view: DragView, source: DragSource, reference_id: str, names: FieldNames
) -> list[str]:
    """Why ``view`` would not show the task's blocks (one line each), or nothing."""
    target = project.stage if view.sprite is None else project.sprite(view.sprite)
    if target is None:
        shown = "the Stage" if view.sprite is None else f"sprite {view.sprite!r}"
        return [f"{names.target}: the view shows {shown}, which the project does not have"]
    problems = []
    holder = project.holder(reference_id)
    if holder is not None and holder is not target:
        problems.append(f"{names.target}: the view shows {target.label} but the reference block is in {holder.label}")
    if isinstance(source, CanvasSource):
        holder = project.holder(source.block_id)
        if holder is not None and holder is not target:
            problems.append(f"{names.target}: the view shows {target.label} but the source block is in {holder.label}")
    if isinstance(source, FlyoutSource):
        expected = palette_category_of(source.opcode)
        if view.category is None:
            problems.append(f"{names.category}: the source comes from the palette but no category is selected")
        elif expected is not None and expected != view.category:
            problems.append(
                f"{names.category}: the view selects {view.category!r} but {source.opcode} is in {expected!r}"
            )
    return problems


def _block(project: ProjectIndex, block_id: str, opcode: str, id_field: str, opcode_field: str) -> list[str]:
    found = project.opcode(block_id)
    if project.holder(block_id) is None:
        return [f"{id_field}: {block_id!r} is not a block of the project"]
    if found != opcode:
        return [f"{opcode_field}: {opcode!r}, but the project's block {block_id!r} is {found!r}"]
    return []
