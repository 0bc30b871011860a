"""Audits of graders: mutants (a project wrong in one small way, which a task's tests should fail) and
refactorings (the same behaviour written otherwise, which they should pass), made from a golden project.

Made through our own program model (``Program``: targets, blocks and their links), never by editing JSON.
"""

from scratchworld_dist.kinds.audit.variants._checks import program_form, structure_problems
from scratchworld_dist.kinds.audit.variants._mutants import OPERATORS, enumerate_mutants, sample_mutants
from scratchworld_dist.kinds.audit.variants._program import (
    Block,
    Field,
    Input,
    Primitive,
    Program,
    ProgramFormatError,
    Target,
)
from scratchworld_dist.kinds.audit.variants._refactorings import (
    REFACTORINGS,
    enumerate_refactorings,
    sample_refactorings,
)
from scratchworld_dist.kinds.audit.variants._variant import (
    Listings,
    Mutant,
    ProgramVariant,
    Refactoring,
    ScriptText,
    script_listings,
)

__all__ = [
    "OPERATORS",
    "REFACTORINGS",
    "Block",
    "Field",
    "Input",
    "Listings",
    "Mutant",
    "Primitive",
    "Program",
    "ProgramFormatError",
    "ProgramVariant",
    "Refactoring",
    "ScriptText",
    "Target",
    "enumerate_mutants",
    "enumerate_refactorings",
    "program_form",
    "sample_mutants",
    "sample_refactorings",
    "script_listings",
    "structure_problems",
]
