"""The perimeter benchmark's analytic helper: the time mean of the worst angle's error when a
stale head's sawtooth rises over a constant floor."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("bench_perimeter", ROOT / "scripts/bench_perimeter.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # its dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


@pytest.mark.parametrize(("floor", "peak"), [(9.0, 50.0), (9.0, 20.0), (9.0, 9.0), (9.0, 3.0), (0.0, 40.0)])
def test_sawtooth_mean_is_the_time_mean_of_the_larger(bench, floor, peak):
    u = (np.arange(200_000) + 0.5) / 200_000  # the sawtooth's phase, uniform over a period
    assert bench._sawtooth_mean(floor, peak) == pytest.approx(np.mean(np.maximum(floor, peak * u)), rel=1e-6)


def test_the_paper_regime_fires_do_what_their_names_say(bench):
    """PM Fig. 16: the fuel-change fire is even until its head reaches the fast fuel (about 2 h),
    then strongly uneven with a head that runs several cells a lap; the wind-driven fire has a
    head well ahead of its median angle from the start. From the arrival times, no flight."""
    fc = {r["hours"]: r for r in bench.describe("fuel change", (1.0, 1.5, 3.0, 3.5))}
    ratio = {h: r["head_mps"] / r["median_mps"] for h, r in fc.items()}
    assert ratio[1.0] < 3.0 and ratio[1.5] < 3.0  # one fuel: mildly wind-driven
    assert ratio[3.0] > 6.0 and ratio[3.5] > 10.0  # the head in the 4x fuel
    assert fc[1.0]["head_cells_per_lap"] < 1.0 < 5.0 < fc[3.5]["head_cells_per_lap"]
    for r in bench.describe("wind-driven", (1.0, 3.0)):
        assert r["head_mps"] > 3.0 * r["median_mps"] and r["lap_s"] > 4 * 60.0  # uneven, long laps


def test_late_mean_counts_only_the_samples_from_the_given_time(bench):
    """--score-from-s: the running average restarted at S, over (t, max, floor) samples."""
    samples = [(10.0, 100.0, 1.0), (20.0, 4.0, 2.0), (30.0, 6.0, 4.0)]
    assert bench.late_mean(samples, 20.0) == (5.0, 3.0)  # t = 20 counts, t = 10 does not
    assert bench.late_mean(samples, 0.0) == (pytest.approx(110.0 / 3), pytest.approx(7.0 / 3))
    assert all(np.isnan(bench.late_mean(samples, 31.0)))  # no sample after S
    assert all(np.isnan(bench.late_mean(samples, None)))  # not asked


def test_the_narrow_head_fire_is_in_pm_fig_16a_regime(bench):
    """The "narrow head" fire: even (every angle within x1.6 of the head) for 3 h, then a head
    ten times faster than the back; over the scored window (3-5 h) nearly convex (its own hull
    outside it by at most 1.5 cells, about what a round fire's squares give) with a fast part
    well under half the perimeter (at a quarter of the head's rate or more: < 0.35). The
    fuel-change fire, for contrast, fails both once its head is in the fast fuel. From the
    arrival times, no flight."""
    cell = bench.CELL_M
    even, *late = bench.regime("narrow head", (2.0, 3.0, 3.5, 4.0, 4.5))
    assert even["fast_share"] == 1.0 and even["head_mps"] < 1.6 * even["median_mps"]
    for r in late:
        assert r["fast_share"] < 0.35, r
        assert r["hull_gap_m"] <= 1.5 * cell and r["floor_m"] <= 1.5 * cell, r
        assert r["head_mps"] > 4.0 * bench.NH_BACK_MPS  # uneven: the head far ahead of the back
    (fc,) = bench.regime("fuel change", (3.0,))
    assert fc["fast_share"] > 0.5 and fc["hull_gap_m"] > 4 * cell  # the fan and the hull's over-reach
