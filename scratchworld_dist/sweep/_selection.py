"""What the diagnostic benchmarks (drag, perception) share when they pick their items: the suites that are here,
and the ids a config names checked against them."""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

from scratchworld_dist._errors import ConfigError

if TYPE_CHECKING:
    from scratchworld_dist.suites import BaseSuite

SuiteT = TypeVar("SuiteT")


def present_suites(
    suite: Path,
    optional: Sequence[Path],
    load: Callable[[Path], SuiteT],
    say: Callable[[str], None],
    *,
    benchmark: str,
    item: str,
) -> list[SuiteT]:
    """``suite`` and each optional suite that is here, loaded; one that is not is said and skipped."""
    found = [load(suite)]
    for path in optional:
        if path.is_dir():
            found.append(load(path))
        else:
            say(f"{benchmark}: optional suite {path} is not here; its {item}s are skipped")
    return found


def wanted_ids(
    ids: Sequence[str], wanted: Sequence[str], *, benchmark: str, item: str, suites: Sequence[BaseSuite[Any]] = ()
) -> set[str]:
    """The ids a config names (``tasks.ids``; empty: all), checked against the suites' ``ids``: an id two suites
    share, or one that names nothing, is a ``ConfigError``; one that ``suites`` left out is named with why."""
    clashes = sorted(i for i, n in Counter(ids).items() if n > 1)
    if clashes:
        raise ConfigError(f"{benchmark} suites share {item} ids: {', '.join(clashes[:10])}")
    unknown = sorted(set(wanted) - set(ids))
    left_out = [f"{i} ({why})" for i in unknown if (why := "; ".join(filter(None, (s.left_out(i) for s in suites))))]
    if left_out:
        raise ConfigError(f"tasks.ids names {benchmark} {item}(s) left out of their suite: {'; '.join(left_out[:3])}")
    if unknown:
        raise ConfigError(f"tasks.ids names {benchmark} {item}(s) not in the suites: {', '.join(unknown[:10])}")
    return set(wanted)
