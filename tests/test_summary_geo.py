"""A mission on a landscape reports its ignitions and UAV homes in degrees too (summary ``geo``)."""

from __future__ import annotations

from fire_mission.inprocess import run_inprocess


def test_inprocess_summary_has_lat_lon_on_a_landscape() -> None:
    d = run_inprocess("worcester_vt", uavs=2, seed=1, max_steps=3)
    geo = d["geo"]
    assert geo["landscape"] == "worcester_vt" and len(geo["uav_homes"]) == 2
    assert all(
        44.3 < p["lat_deg"] < 44.45 and -72.6 < p["lon_deg"] < -72.45
        for p in geo["ignitions"] + geo["uav_homes"]
    )


def test_a_scenario_on_made_up_ground_has_no_geo() -> None:
    assert "geo" not in run_inprocess("tiny_test", uavs=1, seed=1, max_steps=3)
