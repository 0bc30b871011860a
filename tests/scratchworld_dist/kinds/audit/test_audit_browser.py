"""Mutants and refactorings load into the real Scratch editor, whose VM reads them as we wrote them."""

from __future__ import annotations

import io
import json
import zipfile
from collections import Counter

import pytest

from scratchworld_dist.kinds.audit.variants import (
    OPERATORS,
    REFACTORINGS,
    Program,
    enumerate_refactorings,
    program_form,
    sample_mutants,
)
from scratchworld_dist.sb3 import Sb3Archive
from tests.conftest import pooled_editor
from tests.support.audit_projects import mutation_project, refactoring_project
from workers.editor import EditorPool

pytestmark = [pytest.mark.browser, pytest.mark.slow]


def project_json(sb3: bytes) -> dict:
    with zipfile.ZipFile(io.BytesIO(sb3)) as archive:
        return json.loads(archive.read("project.json"))


async def test_variants_load_into_the_real_editor_as_written(shared_pool: EditorPool) -> None:
    """Every refactoring of the refactoring project and a mutant of each operator (a load takes the editor up
    to a second, and 150 mutants of one kind prove little more than one): the VM accepts each, the editor
    shows no page error, and the project it saves again does what ours does (``program_form``)."""
    mutations, refactorings = mutation_project(), refactoring_project()
    mutants = sample_mutants(mutations.to_project_json(), len(OPERATORS), seed=0)
    refactored = enumerate_refactorings(refactorings.to_project_json())
    assert set(Counter(m.operator for m in mutants)) == set(OPERATORS)
    assert set(Counter(r.operator for r in refactored)) == set(REFACTORINGS)
    cases = [(Sb3Archive(mutations.to_sb3()), mutants), (Sb3Archive(refactorings.to_sb3()), refactored)]
    async with pooled_editor(shared_pool) as editor:
        for archive, variants in cases:
            for variant in variants:
                names = await editor.load_project(archive.with_project(variant.project))
                assert names == [t["name"] for t in variant.project["targets"]], variant.change
                saved = project_json(await editor.save_project())
                ours, theirs = program_form(Program.parse(variant.project)), program_form(Program.parse(saved))
                assert theirs == ours, (variant.operator, variant.change)
                assert editor.page_errors == [], variant.change
