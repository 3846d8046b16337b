"""The study's statistics against truths: a paired shift is found and named, noise with no
shift is "no detectable difference", Kaplan-Meier without censoring before the events is the
empirical distribution, censoring at the limit is honoured, Wilcoxon's exact small-sample p."""

from __future__ import annotations

import math

import numpy as np
import pytest
from fire_study.spec import Arm
from fire_study.stats import arm_stats, bootstrap_ci, containment, paired_stats, verdict

A = Arm("grass_running", "default", 6, "head")
B = Arm("grass_running", "default", 6, "flank")


def _rows(arm: Arm, areas, contained=None, limit=900.0) -> list[dict]:
    out = []
    for seed, area in enumerate(areas, 1):
        c = None if contained is None else contained[seed - 1]
        out.append({"scenario": arm.scenario, "airframe": arm.airframe, "uavs": arm.uavs, "tactic": arm.tactic,
                    "seed": seed, "burned_area_m2": area, "contained": c is not None, "contained_at_s": c,
                    "time_limit_s": limit})  # fmt: skip
    return out


def test_a_paired_shift_is_found_and_stated_in_plain_words() -> None:
    rng = np.random.default_rng(1)
    base = rng.uniform(30e4, 50e4, 12)  # seeds differ a lot ...
    rows = _rows(A, base) + _rows(B, base * 0.69 + rng.normal(0, 2e3, 12))  # ... flank ~31 % less in each
    p = paired_stats(rows, A, B, "burned_area_m2")
    assert p.seeds == tuple(range(1, 13))
    assert -0.33 < p.rel_ci[0] < p.rel < p.rel_ci[1] < -0.29
    assert p.wilcoxon_p == pytest.approx(2 / 2**12)  # exact: all 12 differences negative
    v = verdict(p)
    assert v.startswith("on grass_running with 6 UAVs, flank burns 31 % less than head (95 % CI -3")
    assert "12 paired seeds" in v


def test_noise_without_a_shift_is_no_detectable_difference() -> None:
    rng = np.random.default_rng(2)
    base = rng.uniform(30e4, 50e4, 10)
    rows = _rows(A, base + rng.normal(0, 1e4, 10)) + _rows(B, base + rng.normal(0, 1e4, 10))
    p = paired_stats(rows, A, B, "burned_area_m2")
    assert p.rel_ci[0] < 0 < p.rel_ci[1]
    assert "no detectable difference in burned area between flank and head" in verdict(p)


def test_only_seeds_both_arms_ran_are_paired_and_one_seed_gives_no_verdict() -> None:
    rows = _rows(A, [1.0, 2.0, 3.0]) + _rows(B, [1.5])
    p = paired_stats(rows, A, B, "burned_area_m2")
    assert p.seeds == (1,) and p.diffs == (0.5,)
    assert "too few paired seeds (1)" in verdict(p)


def test_bootstrap_ci_of_the_mean_covers_it_and_narrows_with_n() -> None:
    rng = np.random.default_rng(3)
    small, big = rng.normal(10, 2, 8), rng.normal(10, 2, 200)
    lo_s, hi_s = bootstrap_ci((small,), np.mean)
    lo_b, hi_b = bootstrap_ci((big,), np.mean)
    assert lo_s < small.mean() < hi_s and lo_b < big.mean() < hi_b
    assert hi_b - lo_b < hi_s - lo_s
    assert hi_b - lo_b == pytest.approx(2 * 1.96 * big.std(ddof=1) / math.sqrt(200), rel=0.2)  # normal theory
    assert all(math.isnan(v) for v in bootstrap_ci((np.array([5.0]),), np.mean))  # n = 1: no interval
    assert bootstrap_ci((np.array([5.0, 5.0, 5.0]),), np.mean) == (5.0, 5.0)


def test_arm_stats_mean_and_median() -> None:
    s = arm_stats(_rows(A, [1.0, 2.0, 9.0]), A, "burned_area_m2")
    assert (s.n, s.mean, s.median) == (3, 4.0, 2.0)
    assert s.mean_ci[0] <= 4.0 <= s.mean_ci[1]


def test_kaplan_meier_is_the_empirical_distribution_without_censoring_before_the_events() -> None:
    rows = _rows(A, [1] * 5, contained=[100.0, 300.0, 200.0, None, None])
    c = containment(rows, A)
    assert (c.n, c.contained, c.limit_s) == (5, 3, 900.0)
    by_t = dict(zip(c.times_s, c.fraction, strict=True))
    assert by_t[100.0] == pytest.approx(0.2) and by_t[200.0] == pytest.approx(0.4)
    assert by_t[300.0] == pytest.approx(0.6) and by_t[900.0] == pytest.approx(0.6)  # two never contained
    assert c.median_s == 300.0  # the first time more than half are contained
    none = containment(_rows(B, [1, 1], contained=[None, None]), B)
    assert none.contained == 0 and none.median_s is None and max(none.fraction) == 0.0


def test_never_contained_counts_at_the_limit_in_paired_times() -> None:
    rows = _rows(A, [1, 1, 1], contained=[None, None, None]) + _rows(
        B, [1, 1, 1], contained=[700.0, 800.0, 750.0]
    )
    p = paired_stats(rows, A, B, "contained_at_s")
    assert p.diffs == (-200.0, -100.0, -150.0)
