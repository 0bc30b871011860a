"""Variants of a project -- mutants (wrong in one small way) and refactorings (the same behaviour written
otherwise) -- made from candidates, checked, listed before and after, and sampled.

A candidate names one change at one place and knows how to make it on a fresh copy of the program. Making
it keeps the variant only if the result is structurally whole (no problem the original did not already
have) and -- for a mutant -- does something the original does not and no earlier mutant does. (The .sb3
pre-check, ``check_project``, reads only sizes and JSON: a variant of a project that passes it, a few blocks
apart, passes it too; the tests check that it does.)
"""

from __future__ import annotations

import hashlib
import json
import random
from collections.abc import Callable, Collection, Iterable, Sequence
from dataclasses import dataclass
from typing import Any, TypeVar

from pydantic import BaseModel, ConfigDict, Field

from scratchworld_dist.kinds.audit.variants._checks import Form, program_form, structure_problems, target_form
from scratchworld_dist.kinds.audit.variants._program import Block, Program
from scratchworld_dist.sb3 import script_lines


class ProgramVariant(BaseModel):
    """One change of a project at one place, and the project it gives."""

    model_config = ConfigDict(frozen=True)

    operator: str
    """A stable name: ``delete_statement``, ``rename_variable``..."""
    target: str
    """The sprite (or ``Stage``) changed."""
    block_id: str
    """The block changed (for a renamed variable or list: its id)."""
    change: str
    """The change itself, in stable words (``NUM1: 10 -> 11``)."""
    description: str
    before: str
    """Pseudocode of the scripts the change touches, as they were."""
    after: str
    """The same scripts after the change (and any script it added)."""
    project: dict[str, Any] = Field(repr=False)
    """The changed project.json (its assets are the original's: see ``Sb3Archive.with_project``)."""


class Mutant(ProgramVariant):
    """A project wrong in one small way: a sound grader fails it."""

    mutant_id: str
    """A hash of operator, place and change (not of the project: the job that evaluates a mutant hashes its
    bytes), so a mutant keeps its id when an unrelated part of the golden changes."""


class Refactoring(ProgramVariant):
    """A project that behaves as the original, written differently: a sound grader passes it."""

    refactoring_id: str
    """As ``Mutant.mutant_id``."""


Variant = TypeVar("Variant", bound=ProgramVariant)


@dataclass(frozen=True)
class Candidate:
    """A change an operator proposes: where, what, and how to make it on a copy of the program."""

    operator: str
    target: str
    block_id: str
    change: str
    description: str
    apply: Callable[[Program], None]


def variant_id(kind: str, candidate: Candidate) -> str:
    key = [kind, candidate.operator, candidate.target, candidate.block_id, candidate.change]
    return hashlib.sha256(json.dumps(key).encode()).hexdigest()[:16]


@dataclass(frozen=True)
class _Made:
    project: dict[str, Any]
    form: Form
    changed: frozenset[str]
    """The targets whose JSON differs from the original's."""


class VariantMaker:
    """Makes the variants of one project: the original is read, checked and listed once, and of a variant
    only the targets it changed are checked and listed again."""

    def __init__(self, project: dict[str, Any]) -> None:
        self.project = project
        self.program = Program.parse(project)
        self.problems = set(structure_problems(self.program))
        self.forms = {target.name: target_form(target) for target in self.program.targets}
        self.seen: set[Form] = {program_form(self.program)}
        self.listings = script_listings(project)

    def mutants(self, candidates: Iterable[Candidate]) -> list[Mutant]:
        """Mutants in candidate order; a change that does nothing, or what an earlier one did, is left out."""
        made = []
        for candidate in candidates:
            result = self._make(candidate)
            if result is None or result.form in self.seen:
                continue
            self.seen.add(result.form)
            made.append(Mutant(**self._fields(candidate, result), mutant_id=variant_id("mutant", candidate)))
        return made

    def refactorings(self, candidates: Iterable[Candidate]) -> list[Refactoring]:
        """Refactorings in candidate order; one that leaves the project as it was is left out."""
        made = []
        for candidate in candidates:
            result = self._make(candidate)
            if result is not None and result.changed:
                fields = self._fields(candidate, result)
                made.append(Refactoring(**fields, refactoring_id=variant_id("refactoring", candidate)))
        return made

    def _make(self, candidate: Candidate) -> _Made | None:
        """The candidate's project, or None when it breaks a link the original did not break."""
        program = self.program.copy()
        candidate.apply(program)
        project = program.to_project()
        old = {t["name"]: t for t in self.project["targets"]}
        changed = frozenset(t["name"] for t in project["targets"] if _differs(old.get(t["name"]), t))
        only = None if program.stage.name in changed else changed
        if set(structure_problems(program, only)) - self.problems:
            return None
        form = tuple(target_form(t) if t.name in changed else self.forms[t.name] for t in program.targets)
        return _Made(project, form, changed)

    def _place(self, candidate: Candidate) -> tuple[str, str] | None:
        """(target, top block) of the script the candidate changes, if it changes a block."""
        target = next((t for t in self.program.targets if t.name == candidate.target), None)
        if target is None or not isinstance(target.blocks.get(candidate.block_id), Block):
            return None
        return target.name, target.top_of(candidate.block_id)

    def _fields(self, candidate: Candidate, made: _Made) -> dict[str, Any]:
        new = {key: text for key, text in self.listings.items() if key[0] not in made.changed}
        new.update(script_listings(made.project, made.changed))
        before, after = changed_listings(self.listings, new, self._place(candidate))
        return {
            "operator": candidate.operator,
            "target": candidate.target,
            "block_id": candidate.block_id,
            "change": candidate.change,
            "description": candidate.description,
            "before": before,
            "after": after,
            "project": made.project,
        }


def _differs(old: dict[str, Any] | None, new: dict[str, Any]) -> bool:
    """Whether a target changed, in content or in the order of its blocks (the order its scripts start in)."""
    return old != new or list(old["blocks"]) != list(new["blocks"])


@dataclass(frozen=True)
class ScriptText:
    """A script as listed: where it is, its rank among its sprite's scripts (the order they start in), its lines
    and the blocks each line shows."""

    head: str
    rank: int
    lines: tuple[str, ...]
    blocks: tuple[frozenset[str], ...] = ()

    def same(self, other: ScriptText | None) -> bool:
        """The same script in the same place; a rank shifted by another script's move is not a change."""
        return other is not None and (self.head, self.lines) == (other.head, other.lines)

    def text(self) -> str:
        return "\n".join((f"{self.head}, script {self.rank}", *self.lines))


Listings = dict[tuple[str, str], ScriptText]
"""(target, top block) -> the script as listed."""


def changed_listings(old: Listings, new: Listings, place: tuple[str, str] | None) -> tuple[str, str]:
    """Pseudocode of the scripts that differ (in content or place) between ``old`` and ``new``, and always
    of ``place`` (target, top block): as they were, and as they are."""
    keys = [key for key in {**old, **new} if key not in old or not old[key].same(new.get(key))]
    if place is not None and place not in keys:
        keys.insert(0, place)
    return _join(old, keys), _join(new, keys)


def script_listings(project: dict[str, Any], only: Collection[str] | None = None) -> Listings:
    """The scripts of a project (of its targets named ``only``, when given), listed."""
    found = {}
    for target in project["targets"]:
        if only is not None and target.get("name") not in only:
            continue
        kind = "Stage" if target.get("isStage") else "Sprite"
        blocks = target.get("blocks", {})
        tops = [k for k, b in blocks.items() if isinstance(b, dict) and b.get("topLevel") and not b.get("shadow")]
        for rank, block_id in enumerate(tops, 1):
            block = blocks[block_id]
            head = f"== {kind}: {target.get('name')} (at {block.get('x')}, {block.get('y')})"
            listed = script_lines(blocks, block_id)
            lines, shown = tuple(line.text for line in listed), tuple(line.blocks for line in listed)
            found[(str(target.get("name")), block_id)] = ScriptText(head, rank, lines, shown)
    return found


def _join(scripts: Listings, keys: Sequence[tuple[str, str]]) -> str:
    parts = [scripts[key].text() for key in keys if key in scripts]
    return "\n\n".join(parts) or "(nothing)"


def sample(variants: Sequence[Variant], n: int, seed: int | str) -> list[Variant]:
    """``n`` of ``variants``, spread over operators (one of each in turn, in a seeded order), chosen by
    ``seed`` alone; returned in their order in ``variants``."""
    if n < 0:
        raise ValueError(f"cannot sample {n} variants")
    rng = random.Random(f"audit-sample:{seed}")
    groups: dict[str, list[int]] = {}
    for index, variant in enumerate(variants):
        groups.setdefault(variant.operator, []).append(index)
    for indices in groups.values():
        rng.shuffle(indices)
    operators = sorted(groups)
    rng.shuffle(operators)
    chosen: list[int] = []
    while len(chosen) < min(n, len(variants)):
        for operator in operators:
            if groups[operator] and len(chosen) < n:
                chosen.append(groups[operator].pop())
    return [variants[index] for index in sorted(chosen)]
