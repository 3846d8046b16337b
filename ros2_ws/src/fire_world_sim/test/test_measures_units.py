"""Suppression measures as units (no fire model, fast): containment against a brute-force oracle
of its written definition, drop accounting and the area history.

The world-level measures tests (real raster fires) are in test_measures.py; this file is what the
mutation run of fire_world_sim.measures selects (config/mutation.toml).
"""

from __future__ import annotations

import math

import pytest
from fire_world_sim.measures import Containment, SuppressionMeasures
from hypothesis import given, settings
from hypothesis import strategies as st


def oracle_contained_at(history: list[tuple[float, float, bool]], window_s: float) -> float | None:
    """The docstring's definition, by brute force over the whole history: quiet at t = nothing
    burns or no ignition in (t - window, t]; contained_at = the first update of the final run of
    quiet updates (None if the latest update is not quiet)."""
    quiet = [(not b) or (last <= t - window_s + 1e-9) for t, last, b in history]
    if not quiet or not quiet[-1]:
        return None
    k = len(quiet) - 1
    while k > 0 and quiet[k - 1]:
        k -= 1
    return history[k][0]


@settings(max_examples=25, deadline=None)
@given(
    st.lists(
        st.tuples(st.sampled_from([0.5, 5.0, 20.0, 30.0, 60.0]), st.booleans(), st.booleans()),
        min_size=1,
        max_size=25,
    )
)
def test_containment_matches_its_definition_on_any_history(steps) -> None:
    c = Containment(window_s=60.0)
    t, last, history, was_burning = 0.0, -math.inf, [], True
    for dt, ignite, keeps_burning in steps:
        t += dt
        if ignite:
            last = t - 0.25  # a cell ignited during this update
        burning = ignite or (was_burning and keeps_burning)  # a fire that is out stays out unless re-lit
        was_burning = burning
        history.append((t, last, burning))
        got = c.update(t, last, burning)
        assert got == oracle_contained_at(history, 60.0)
        assert got == c.contained_at_s
        if got is not None and burning:
            assert got >= last + 60.0 - 1e-9  # contained only a full window after the last cell


def test_default_window_is_sixty_seconds_and_exactly_a_window_is_enough() -> None:
    c = Containment()  # contained: "no front cell advancing for 60 s"
    assert c.update(0.0, 0.0, True) is None
    assert c.update(59.5, 0.0, True) is None
    assert c.update(60.0, 0.0, True) == 60.0
    assert isinstance(c.contained_at_s, float)


def test_containment_accepts_any_positive_window_and_repeated_times() -> None:
    c = Containment(window_s=0.5)
    assert c.update(1.0, 0.75, True) is None
    assert c.update(1.0, 0.75, True) is None  # same time again: non-decreasing is allowed
    assert c.update(1.25, 0.75, True) == 1.25
    with pytest.raises(ValueError, match=r"window_s must be > 0, got -1"):
        Containment(window_s=-1.0)
    with pytest.raises(ValueError, match=r"window_s must be > 0, got 0"):
        Containment(window_s=0.0)
    with pytest.raises(ValueError, match=r"must not go back in time \(0.5 < 1.25\)"):
        c.update(0.5, 0.25, True)


def test_drop_accounting() -> None:
    s = SuppressionMeasures()
    assert s.hit_rate is None and s.as_dict()["hit_rate"] is None
    assert s.add_drop(0.0, 5, 40, hit=True) == 0.0  # empty tank: no drop
    assert s.add_drop(-1.0, 5, 40, hit=True) == 0.0
    assert (s.drops, s.hits, s.water_released_kg) == (0, 0, 0.0)
    assert s.add_drop(2000.0, 10, 40, hit=True) == pytest.approx(500.0)  # a quarter of the cells burn
    assert s.add_drop(1000.0, 0, 40, hit=False) == 0.0
    assert s.add_drop(800.0, 0, 0, hit=True) == 800.0  # analytic hit: no cells, the whole load
    assert s.add_drop(600.0, 0, 0, hit=False) == 0.0  # analytic miss
    assert s.add_drop(400.0, 40, 40, hit=True) == 400.0  # every cell burning: all of it
    assert s.add_drop(0.5, 1, 2, hit=True) == 0.25  # a small release is still a drop
    assert s.add_drop(100.0, 1, 1, hit=False) == 100.0  # a one-cell footprint, burning
    assert s.as_dict() == {
        "drops": 7,
        "hits": 4,
        "hit_rate": pytest.approx(4 / 7),
        "water_released_kg": pytest.approx(4900.5),
        "water_on_burning_kg": pytest.approx(1800.25),
        "burned_area_m2": 0.0,
        "contained_at_s": None,
    }


def test_area_history_is_sampled_once_a_period_and_the_latest_area_is_kept() -> None:
    s = SuppressionMeasures()  # default period 1 s
    t = 0.0
    for k in range(101):  # 10 s in 0.1 s updates, times accumulated as the world does (inexact)
        s.update(t, burned_area_m2=float(k), last_ignition_s=t, burning=True)
        t += 0.1
    assert len(s.area_t_s) == 11 and s.area_t_s[0] == 0.0 and s.area_t_s[-1] == pytest.approx(10.0)
    assert s.area_m2 == [float(10 * k) for k in range(11)]
    assert s.burned_area_m2 == 100.0 and s.as_dict()["burned_area_m2"] == 100.0
    assert s.as_dict()["contained_at_s"] is None  # still spreading
    slow = SuppressionMeasures(area_every_s=5.0)
    for k in range(11):
        slow.update(float(k), 1.0, last_ignition_s=-math.inf, burning=False)
    assert slow.area_t_s == [0.0, 5.0, 10.0]
    assert slow.containment.contained_at_s == 0.0  # nothing burning from the start
