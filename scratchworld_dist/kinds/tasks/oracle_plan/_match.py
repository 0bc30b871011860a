"""Which block of the initial project becomes which block of the golden one.

A block kept is a block not rebuilt, so the matching decides how short a plan is. Scripts are
paired by how much of them agrees; within a pair, chains are aligned like sequences (the longest
run of agreeing blocks, weighted by how much of each block agrees) and aligned blocks pair up
their inputs the same way. Blocks left over are paired by opcode wherever they are, so a block
that only moved (the typical debug fix) is moved, not deleted and rebuilt.
"""

from __future__ import annotations

from functools import cache

from scratchworld_dist.kinds.tasks.oracle_plan._state import TargetState
from scratchworld_dist.kinds.tasks.oracle_plan._tree import (
    block_order,
    chain,
    fields_of,
    held_inputs,
    literals_of,
    preorder,
    top_blocks,
)

Matching = dict[str, str]
"""Golden block id -> initial block id."""


def match_blocks(golden: TargetState, initial: TargetState) -> Matching:
    """Ties are broken by where blocks sit in their scripts (``block_order``), never by id."""
    aligner = _Aligner(golden, initial)
    g_order, i_order = block_order(golden), block_order(initial)
    pairs = sorted(
        (
            (score, g_top, i_top)
            for g_top in top_blocks(golden)
            for i_top in top_blocks(initial)
            if (score := aligner.chains(g_top, i_top)) > 0
        ),
        key=lambda item: (-item[0], g_order[item[1]], i_order[item[2]]),
    )
    matching: Matching = {}
    used: set[str] = set()
    for _, g_top, i_top in pairs:
        if g_top in matching or i_top in used:
            continue
        for g_id, i_id in aligner.chain_pairs(g_top, i_top):
            if g_id not in matching and i_id not in used:
                matching[g_id] = i_id
                used.add(i_id)
    _match_leftovers(golden, initial, matching, used, aligner, i_order)
    return matching


def _match_leftovers(
    golden: TargetState,
    initial: TargetState,
    matching: Matching,
    used: set[str],
    aligner: _Aligner,
    i_order: dict[str, int],
) -> None:
    free = [i_id for i_id in preorder(initial) if i_id not in used]
    for g_id in [g_id for g_id in preorder(golden) if g_id not in matching]:
        opcode = golden.blocks[g_id].opcode
        candidates = [i_id for i_id in free if initial.blocks[i_id].opcode == opcode]
        if not candidates:
            continue
        best = max(candidates, key=lambda i_id: (aligner.blocks(g_id, i_id), -i_order[i_id]))
        matching[g_id] = best
        used.add(best)
        free.remove(best)


class _Aligner:
    """Similarity of blocks and chains between the two targets, memoised (scores only grow with agreement)."""

    def __init__(self, golden: TargetState, initial: TargetState) -> None:
        self.golden, self.initial = golden, initial
        self.blocks = cache(self._blocks)
        self._chain_table = cache(self._table)

    def _blocks(self, g_id: str, i_id: str) -> float:
        g, i = self.golden.blocks[g_id], self.initial.blocks[i_id]
        if g.opcode != i.opcode:
            return 0.0
        score = 1.0
        score += 0.5 if fields_of(g) == fields_of(i) else 0.0
        score += 0.25 if literals_of(self.golden, g) == literals_of(self.initial, i) else 0.0
        held = dict(held_inputs(i))
        for name, g_child in held_inputs(g):
            if name in held:
                score += self.chains(g_child, held[name])
        return score

    def chains(self, g_first: str, i_first: str) -> float:
        table, g_ids, i_ids = self._chain_table(g_first, i_first)
        return table[len(g_ids)][len(i_ids)]

    def _table(self, g_first: str, i_first: str) -> tuple[list[list[float]], list[str], list[str]]:
        g_ids, i_ids = chain(self.golden, g_first), chain(self.initial, i_first)
        table = [[0.0] * (len(i_ids) + 1) for _ in range(len(g_ids) + 1)]
        for a in range(1, len(g_ids) + 1):
            for b in range(1, len(i_ids) + 1):
                pair = self.blocks(g_ids[a - 1], i_ids[b - 1])
                best = max(table[a - 1][b], table[a][b - 1])
                table[a][b] = max(best, table[a - 1][b - 1] + pair) if pair > 0 else best
        return table, g_ids, i_ids

    def chain_pairs(self, g_first: str, i_first: str) -> list[tuple[str, str]]:
        """Aligned blocks of two chains, and recursively of the inputs of each aligned pair."""
        table, g_ids, i_ids = self._chain_table(g_first, i_first)
        pairs: list[tuple[str, str]] = []
        a, b = len(g_ids), len(i_ids)
        while a > 0 and b > 0:
            pair = self.blocks(g_ids[a - 1], i_ids[b - 1])
            if pair > 0 and table[a][b] == table[a - 1][b - 1] + pair:
                pairs.append((g_ids[a - 1], i_ids[b - 1]))
                a, b = a - 1, b - 1
            elif table[a][b] == table[a - 1][b]:
                a -= 1
            else:
                b -= 1
        result: list[tuple[str, str]] = []
        for g_id, i_id in reversed(pairs):
            result.append((g_id, i_id))
            held = dict(held_inputs(self.initial.blocks[i_id]))
            for name, g_child in held_inputs(self.golden.blocks[g_id]):
                if name in held:
                    result.extend(self.chain_pairs(g_child, held[name]))
        return result
