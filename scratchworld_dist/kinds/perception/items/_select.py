"""Choosing the items of a suite from every view's candidates: balanced, spread over views, repeatable.

Views take turns (in id order); each picks, among its candidates, the one whose (kind, answer) bucket is
smallest so far, then whose tag is rarest, then about a block it has not asked about yet, then the first
in its seeded shuffle, until it holds ``per_view`` items or has nothing left. Then, within each kind, the
larger of YES and NO loses its last picks (from the fullest views first) until the two are equal. The same
candidates and seed give the same items.
"""

from __future__ import annotations

import random
from collections import Counter, defaultdict
from collections.abc import Mapping, Sequence

from scratchworld_dist.kinds.perception.items._candidates import Candidate
from workers.kinds.perception import NO, YES


def select(candidates: Mapping[str, Sequence[Candidate]], *, per_view: int, seed: int) -> dict[str, list[Candidate]]:
    """Per view id, the candidates chosen (at most ``per_view``), in the order they were picked."""
    if per_view < 1:
        raise ValueError(f"per_view must be at least 1, not {per_view}")
    pools: dict[str, list[Candidate]] = {}
    for view in sorted(candidates):
        pool = list(candidates[view])
        random.Random(f"{seed}:{view}").shuffle(pool)
        pools[view] = pool
    buckets: Counter[tuple[str, str]] = Counter()
    tags: Counter[str] = Counter()
    chosen: dict[str, list[Candidate]] = defaultdict(list)
    order: list[tuple[str, Candidate]] = []
    active = [view for view in pools if pools[view]]
    while active:
        for view in list(active):
            pool, mine = pools[view], chosen[view]
            asked = Counter(c.subject for c in mine if c.subject is not None)
            pick = min(
                range(len(pool)),
                key=lambda i: (
                    buckets[(pool[i].kind, pool[i].answer_class)],
                    tags[pool[i].derived.tag],
                    asked[pool[i].subject] if pool[i].subject is not None else 0,
                    i,
                ),
            )
            candidate = pool.pop(pick)
            mine.append(candidate)
            order.append((view, candidate))
            buckets[(candidate.kind, candidate.answer_class)] += 1
            tags[candidate.derived.tag] += 1
            if len(mine) >= per_view or not pool:
                active.remove(view)
    return _balanced(chosen, order)


def _balanced(chosen: dict[str, list[Candidate]], order: list[tuple[str, Candidate]]) -> dict[str, list[Candidate]]:
    """``chosen`` with YES and NO made equal within each kind, dropping the latest picks of the fullest views."""
    counts: Counter[tuple[str, str]] = Counter((c.kind, c.answer_class) for _, c in order)
    for kind in sorted({c.kind for _, c in order}):
        surplus = counts[(kind, YES)] - counts[(kind, NO)]
        extra = YES if surplus > 0 else NO
        for _ in range(abs(surplus)):
            fullest = max(
                (
                    view
                    for view, items in chosen.items()
                    if any(c.kind == kind and c.answer_class == extra for c in items)
                ),
                key=lambda view: (len(chosen[view]), view),
            )
            items = chosen[fullest]
            last = max(i for i, c in enumerate(items) if c.kind == kind and c.answer_class == extra)
            del items[last]
    return {view: items for view, items in chosen.items() if items}
