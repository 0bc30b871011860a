"""The flake finder's plan and verdict rules, on recorded runs (no browser)."""

from __future__ import annotations

from scratchworld_dist.kinds.tasks.flakes import FlakeRun, FlakeSettings, Variant, plan_variants, stability_of_tests


def test_the_plan_varies_one_axis_at_a_time_from_a_baseline_and_repeats_from_its_seed() -> None:
    settings = FlakeSettings(runs=3, seed=5)
    variants = plan_variants(settings, "virtual", "on_demand")
    assert variants == plan_variants(settings, "virtual", "on_demand")
    assert variants[0].axis == "baseline" and variants[0].perturbation.phase_ms == 0
    counts = {axis: sum(v.axis == axis for v in variants) for axis in settings.axes}
    assert counts == {"seed": 3, "phase": 3, "mouse": 3, "lateness": 6, "clock": 3, "render": 1, "load": 3}
    base = variants[0].perturbation
    for variant in variants[1:]:
        changed = {
            name
            for name in ("random_seed", "phase_ms", "mouse", "lateness")
            if getattr(variant.perturbation, name) != getattr(base, name)
        }
        expected = {"seed": {"random_seed"}, "phase": {"phase_ms"}, "mouse": {"mouse"}, "lateness": {"lateness"}}
        assert changed == (set() if variant.timing == "calibrated" else expected.get(variant.axis, set())), variant
    assert [v.perturbation.phase_ms for v in variants if v.axis == "phase"] == [8.2, 16.5, 24.8]
    assert {v.clock for v in variants if v.axis == "clock"} == {"real"}
    # The lateness levels on ideal timing, then the calibrated frame timing once.
    assert [v.timing for v in variants if v.axis == "lateness"] == ["ideal"] * 5 + ["calibrated"]
    assert all(v.cpu_load == 2 for v in variants if v.axis == "load")
    # Phase and lateness exist in virtual time only, whatever the baseline clock.
    real = plan_variants(settings, "real", "every_frame")
    assert {v.clock for v in real if v.axis in ("phase", "lateness")} == {"virtual"}
    assert {v.render for v in real if v.axis == "render"} == {"on_demand"}


def _run(variant: Variant, which: str, category: str, verdicts: dict[str, bool], error: str | None = None) -> FlakeRun:
    return FlakeRun(
        task_id="t",
        category=category,
        which=which,  # type: ignore[arg-type]
        variant=variant,
        verdicts=verdicts,
        error=error,
        load_average=0.5,
        wall_s=0.1,
    )


def test_a_flip_makes_a_test_unstable_and_only_goldens_and_debug_initials_block() -> None:
    variants = plan_variants(
        FlakeSettings(runs=1, axes=("seed", "lateness"), lateness_ms=(0, 25)), "virtual", "on_demand"
    )
    assert [v.axis for v in variants] == ["baseline", "seed", "lateness", "lateness", "lateness"]
    baseline, seed, on_time, late, calibrated = variants

    def runs(category: str) -> list[FlakeRun]:
        return [
            _run(baseline, "golden", category, {"a": True, "b": True}),
            _run(seed, "golden", category, {"a": True, "b": True}),
            _run(on_time, "golden", category, {"a": True, "b": True}),
            _run(late, "golden", category, {"a": False, "b": True}),
            _run(calibrated, "golden", category, {"a": True, "b": False}),
            _run(baseline, "initial", category, {"a": False}),
            _run(seed, "initial", category, {}, error="script_timeout: too slow"),
            _run(on_time, "initial", category, {"a": False}),
            _run(late, "initial", category, {"a": False}),
            _run(calibrated, "initial", category, {"a": False}),
        ]

    rows = {(row.which, row.test): row for row in stability_of_tests(runs("create"))}
    a = rows[("golden", "a")]
    assert not a.stable and a.blocking and a.baseline == "pass" and (a.flipped, a.runs) == (1, 5)
    assert a.rate == 0.25 and a.rate_by_axis == {"seed": 0.0, "lateness": 0.333}
    assert [(f.axis, f.verdict) for f in a.flips] == [("lateness", "fail")]
    assert a.lateness_band is not None and (a.lateness_band.passes_ms, a.lateness_band.fails_ms) == ([0], [25])
    assert a.lateness_band.min_fps == a.lateness_band.max_fps == 30.3
    assert (a.lateness_band.calibrated, a.lateness_band.depends_on_timing) == ("pass", False)
    b = rows[("golden", "b")]  # passes at every fixed lateness, fails under the calibrated model only
    assert not b.stable and b.lateness_band is not None and b.lateness_band.fails_ms == []
    assert (b.lateness_band.calibrated, b.lateness_band.depends_on_timing) == ("fail", True)
    initial = rows[("initial", "a")]  # a failed evaluation is a verdict of its own
    assert not initial.stable and not initial.blocking and initial.flips[0].verdict == "error"
    debug = {(row.which, row.test): row for row in stability_of_tests(runs("debug"))}
    assert debug[("initial", "a")].blocking
