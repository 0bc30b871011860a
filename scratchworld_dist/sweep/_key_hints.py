""" "Did you mean" for a config key no model knows (``limits.retires``): the keys its place takes, by similarity.

The place is found from the error's path: the sweep config's fields, a kind's section under its key
(``episodes:``), and the models their fields hold (through lists and optional values alike).
"""

from __future__ import annotations

import difflib
import typing
from collections.abc import Sequence

from pydantic import BaseModel

from scratchworld_dist.kinds import job_kinds


def _inner_model(annotation: object) -> type[BaseModel] | None:
    """The model a field holds: itself, or inside ``list[...]``, ``X | None``, ``dict[str, X]``..."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in typing.get_args(annotation):
        found = _inner_model(arg)
        if found is not None:
            return found
    return None


def _keys(model: type[BaseModel], top: bool) -> list[str]:
    keys = [field.alias or name for name, field in model.model_fields.items() if name != "sections" or not top]
    if top:
        keys += [kind.section_key() for kind in job_kinds() if kind.config_section is not None]
    return keys


def known_keys(root: type[BaseModel], path: Sequence[int | str]) -> list[str] | None:
    """The keys the mapping at ``path`` (under the sweep config ``root``) takes; None when it is not a model's."""
    model, top = root, True
    for part in path:
        if isinstance(part, int):
            continue  # a list item: the field's model already is the item's
        sections = {kind.section_key(): kind.config_section for kind in job_kinds()} if top else {}
        field = model.model_fields.get(part)
        found = sections.get(part) if field is None else _inner_model(field.annotation)
        if found is None:
            return None
        model, top = found, False
    return _keys(model, top)


def unknown_key_message(root: type[BaseModel], loc: Sequence[int | str]) -> str:
    """What to say of the unknown key at ``loc``: that it is unknown, and the closest known key if one is close."""
    keys = known_keys(root, loc[:-1]) or []
    close = difflib.get_close_matches(str(loc[-1]), keys, n=1, cutoff=0.6)
    return f"unknown key; did you mean {close[0]!r}?" if close else "unknown key"
