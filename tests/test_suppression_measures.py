"""Suppression measures recomputed from recorded data (fire_report) against the world's own.

The world (``fire_world_sim.measures``) uses cell ignition times; the report and the live
summary use the burned-area history and the DROP events the bag holds. Two implementations of
one definition: they must agree.
"""

from __future__ import annotations

import numpy as np
import pytest
from fire_mission.summary import LiveEvent, LiveSummary
from fire_report.metrics import containment_from_area, drop_outcomes
from fire_uav_common.constants import EventType, FireStatus
from fire_uav_common.scenario import scenario_from_dict
from fire_world_sim.world import World

PLOT = {
    "name": "plot",
    "area": {"x_min_m": 0, "x_max_m": 150, "y_min_m": 0, "y_max_m": 100},
    "timing": {"max_duration_s": 600.0},
    "uavs": {"first": {"x_m": 10.0, "y_m": 10.0}, "spacing": {"dx_m": 10.0, "dy_m": 0.0}},
    "fires": {
        "model": "raster",
        "raster": {
            "cell_size_m": 5.0, "nx": 30, "ny": 20, "fuel_model": 1, "moisture": 0.06,
            "wind": [{"start_s": -60.0, "speed_mps": 3.0, "direction_deg": 0.0}],
            "ignitions": [{"x_m": 20.0, "y_m": 50.0, "start_s": -60.0}],
        },
    },
}  # fmt: skip


def test_containment_from_the_area_history_matches_the_worlds() -> None:
    w = World(scenario_from_dict(PLOT), no_fleet=True)
    t, area, active = [], [], []
    while not w.complete:
        r = w.step({})
        t.append(r.stamp_ns * 1e-9)
        area.append(sum(f.area_m2 for f in r.fires))
        active.append(any(f.status == FireStatus.ACTIVE for f in r.fires))
    world = w.measures.containment.contained_at_s
    assert (
        world is not None and 60.0 < world < 600.0
    )  # the plot burns to its edges (backing: ~7 min), then is quiet
    got = containment_from_area(np.array(t), np.array(area), np.array(active), raster=True)
    assert got == pytest.approx(world, abs=0.6)
    assert area[-1] == pytest.approx(w.measures.burned_area_m2) == pytest.approx(600 * 25.0)


def test_containment_from_area_is_none_while_growing_and_resets_on_a_breach() -> None:
    t = np.arange(0.0, 200.0, 1.0)
    grow = np.minimum(t, 50.0)  # grows until 50 s
    assert containment_from_area(t, grow, np.ones(t.size, bool), raster=True) == 110.0
    breach = grow + (t >= 150.0)  # grows again at 150 s
    assert containment_from_area(t, breach, np.ones(t.size, bool), raster=True) is None
    assert (
        containment_from_area(t, t, np.zeros(t.size, bool), raster=True) == 0.0
    )  # nothing active: contained


def test_hit_rate_and_water_on_burning_cells_from_drop_events() -> None:
    ev = [
        LiveEvent(1.0, EventType.DROP, 0, -1, 0, 2000.0, "hit fires [0], 12 of 48 cells burning"),
        LiveEvent(2.0, EventType.DROP, 1, -1, -1, 2000.0, "missed, 0 of 48 cells burning"),
        LiveEvent(3.0, EventType.DROP, 1, -1, -1, 0.0, "tank empty"),  # no water: not a drop
    ]
    d = drop_outcomes(ev, is_raster=True)
    assert (d["drops"], d["hits"], d["hit_rate"]) == (2, 1, 0.5)
    assert d["water_on_burning_kg"] == pytest.approx(500.0)
    s = LiveSummary(uav_count=2, raster=True)
    for e in ev:
        s.add(e)
    s.add_truth(0.0, [(10.0, True)])
    out = s.as_dict(outcome="time_limit", wall_s=1.0, steps=10)
    assert out["hit_rate"] == 0.5 and out["burned_area_m2"] == 10.0 and out["contained_at_s"] is None


def test_inprocess_summary_reports_the_burned_area_the_world_has() -> None:
    """``python -m fire_mission.inprocess`` fills burned_area_m2 from the world's truth (it was
    null: the in-process runner never fed the truth to the summary)."""
    from fire_mission.inprocess import run_inprocess

    steps = 1  # one world step: the agents' first payload requests act at the next one
    d = run_inprocess(scenario_from_dict(PLOT), uavs=1, seed=1, max_steps=steps)
    assert d["drops_total"] == 0
    w = World(scenario_from_dict(PLOT), no_fleet=True)
    for _ in range(steps):
        r = w.step({})
    assert d["burned_area_m2"] == pytest.approx(sum(f.area_m2 for f in r.fires))
    assert d["burned_area_m2"] > 0
