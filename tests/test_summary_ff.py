"""FF fields of summary.json (fire_mission.summary): hit rate, refill cycles vs lake passes,
separation, landing at home. Events are written by hand; expected numbers are counted by hand."""

import math

import pytest
from fire_mission.summary import LiveEvent, LiveSummary
from fire_uav_common.constants import EventType


def ev(t, typ, uav=0, fire=-1, value=0.0, x=math.nan, y=math.nan):
    return LiveEvent(t, int(typ), uav, -1, fire, value, "", x, y)


def test_one_refill_cycle_of_three_passes_counts_as_one_cycle_and_three_passes():
    s = LiveSummary(uav_count=2)
    for e in [
        ev(10, EventType.DROP, 0, 0, 2000),
        ev(20, EventType.REFILL, 0, value=300),  # left the lake part-filled
        ev(25, EventType.REFILL, 0, value=900),
        ev(30, EventType.REFILL, 0, value=800),  # full
        ev(40, EventType.DROP, 0, -1, 2000),  # missed
        ev(50, EventType.REFILL, 0, value=2000),
        ev(12, EventType.DROP, 1, 1, 2000),
        ev(22, EventType.REFILL, 1, value=2000),
        ev(23, EventType.REFILL, 1, value=0.0),  # took nothing: not a pass
        ev(60, EventType.DROP, 1, 1, 0.0),  # empty tank: not a drop
    ]:
        s.add(e)
    d = s.as_dict(outcome="complete", wall_s=1.0, steps=10)
    assert d["refills"] == 3  # uav 0: after 10 s and after 40 s; uav 1: after 12 s
    assert d["lake_passes"] == 5
    assert d["drops_total"] == 3 and d["hit_rate"] == pytest.approx(2 / 3, abs=1e-4)


def test_landing_error_is_the_distance_from_touchdown_to_the_takeoff_point():
    s = LiveSummary(uav_count=3)
    s.home_xy = {0: (50.0, 250.0), 1: (50.0, 280.0), 2: (50.0, 310.0)}
    s.add(ev(90, EventType.LANDED, 0, x=53.0, y=254.0))
    s.add(ev(91, EventType.LANDED, 1, x=50.0, y=280.0))
    s.add(ev(95, EventType.LANDED, 1, x=10.0, y=10.0))  # a second event does not move the touchdown
    s.observe_truth(math.inf, 0)
    s.observe_truth(14.5, 0)
    s.observe_truth(12.0, 1)
    s.observe_truth(13.0, 1)  # the world's running minimum: the summary keeps the smallest
    d = s.as_dict(outcome="complete", wall_s=1.0, steps=10)
    assert d["landing_error_m"] == {"0": 5.0, "1": 0.0}  # uav 2 never landed
    assert d["touchdown_spacing_m"] == pytest.approx(math.hypot(3.0, 26.0), abs=1e-3)
    assert d["min_separation_m"] == 12.0 and d["collisions"] == 1


def test_no_drops_no_hit_rate_and_no_airborne_pair_no_separation():
    d = LiveSummary(uav_count=1).as_dict(outcome="time_limit", wall_s=1.0, steps=1)
    assert d["hit_rate"] is None and d["min_separation_m"] is None and d["refills"] == 0
