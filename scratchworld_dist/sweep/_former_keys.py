"""Sweep config keys that moved from the top level into a kind's section (``max_steps`` into ``episodes:``).

A kind's section model lists the keys it took over in ``former_keys``. Configs written before still read: each
such key is moved into its section before validation, so the same sweep validates to the same config (and plans
the same jobs) in either layout. A file or a ``--set`` that uses one is told where it lives now, one notice per
key; stored configs (run manifests) are moved silently. A key given in both places is an error, since one would
silently win over the other.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

from scratchworld_dist._console import make_console
from scratchworld_dist.kinds import job_kind, job_kinds

Notice = Callable[[str], None]
"""Where loading and planning say what they noticed (an old key moved, a missing optional suite left out)."""


def moved_keys() -> dict[str, str]:
    """Each former top-level key of the installed kinds' sections, and the key of the section it is in now."""
    moved: dict[str, str] = {}
    for kind in job_kinds():
        section = kind.config_section
        for key in getattr(section, "former_keys", ()) if section is not None else ():
            moved[key] = kind.section_key()
    return moved


def moved_notice(key: str, section: str) -> str:
    """What a config that writes ``key`` at the top level is told."""
    return f"notice: {key} is now {section}.{key}"


def into_sections(data: Mapping[str, Any]) -> tuple[dict[str, Any], list[str]]:
    """``data`` with every former top-level key moved into its section, and a notice for each one moved;
    ``ValueError`` when a key is given both at the top level and in its section."""
    result, notices = dict(data), []
    for key, section in moved_keys().items():
        if key not in result:
            continue
        current = result.get(section)
        if current is None:
            current = {}
        if not isinstance(current, Mapping):
            continue  # left where it is: validation names the section that is not a mapping
        if key in current:
            raise ValueError(f"{key} is given both at the top level and as {section}.{key}: keep {section}.{key} only")
        result[section] = {**current, key: result.pop(key)}
        notices.append(moved_notice(key, section))
    return result, notices


def stored_layout(config: Mapping[str, Any]) -> dict[str, Any]:
    """A stored config (a run manifest's, in whichever layout the code of its time wrote) in today's layout."""
    try:
        return into_sections(config)[0]
    except ValueError:  # no code ever wrote both; read it as it stands
        return dict(config)


def stored_section(config: Mapping[str, Any], kind: str) -> dict[str, Any]:
    """Kind ``kind``'s section of a stored config, in whichever layout it was written (empty: it has none)."""
    section = stored_layout(config).get(job_kind(kind).section_key())
    return dict(section) if isinstance(section, Mapping) else {}


def stderr_notice(message: str) -> None:
    """Say ``message`` on standard error, as commands say what they noticed."""
    make_console(stderr=True).print(message, markup=False)
