"""The flake finder: evaluate goldens and initials under perturbations that must not change a verdict."""

from scratchworld_dist.kinds.tasks.flakes._analysis import (
    EVALUATION_TEST,
    FlakeConditions,
    FlakeReport,
    Flip,
    LatenessBand,
    TestStability,
    stability_of_tests,
)
from scratchworld_dist.kinds.tasks.flakes._findings import suite_stability
from scratchworld_dist.kinds.tasks.flakes._plan import (
    AXES,
    DEFAULT_LATENESS_MS,
    Axis,
    FlakeSettings,
    Variant,
    plan_variants,
)
from scratchworld_dist.kinds.tasks.flakes._runner import FlakeRun, run_flakes, variant_spec

__all__ = [
    "AXES",
    "DEFAULT_LATENESS_MS",
    "EVALUATION_TEST",
    "Axis",
    "FlakeConditions",
    "FlakeReport",
    "FlakeRun",
    "FlakeSettings",
    "Flip",
    "LatenessBand",
    "TestStability",
    "Variant",
    "plan_variants",
    "run_flakes",
    "stability_of_tests",
    "suite_stability",
    "variant_spec",
]
