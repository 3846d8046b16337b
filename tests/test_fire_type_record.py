"""The fire type per cell of a fire on a landscape: in summary.json, in the summary table and in
the report's fires section; absent for every other fire."""

import numpy as np
from fire_mission.summary import LiveSummary, table
from fire_report.page import fire_types_html


def test_summary_counts_the_burnt_cells_of_each_fire_type():
    s = LiveSummary(uav_count=1)
    grid = np.array([[0, 1, 1, 2], [3, 1, 0, 0]], dtype=np.int8)  # as /world/fire_type carries it
    s.add_fire_types(grid)
    d = s.as_dict(outcome="time_limit", wall_s=1.0, steps=1)
    assert d["fire_type_cells"] == {"surface": 3, "passive_crown": 1, "active_crown": 1}
    assert "surface: 3" in table(d)
    s.add_fire_types(np.zeros_like(grid))  # the newest grid wins
    assert s.as_dict(outcome="time_limit", wall_s=1.0, steps=1)["fire_type_cells"]["surface"] == 0


def test_no_fire_type_key_without_a_landscape_fire():
    d = LiveSummary(uav_count=1).as_dict(outcome="time_limit", wall_s=1.0, steps=1)
    assert "fire_type_cells" not in d
    assert "fire type" not in table(d)
    assert fire_types_html({}) == ""


def test_report_table_gives_cells_area_and_share_per_fire_type():
    html = fire_types_html(
        {"fire_type_cells": {"surface": 30, "passive_crown": 9, "active_crown": 1}, "fire_type_cell_m": 30.0}
    )
    assert "passive crown" in html and "active crown" in html
    # 30 cells of 900 m^2 = 2.70 ha, 75.0 % of 40 cells
    assert ">2.70<" in html and ">75.0<" in html and ">0.09<" in html and ">2.5<" in html


def test_report_shows_the_ground_notes_of_the_run(tmp_path):
    """Water left out as too small for a refill pass reaches the report from summary.json."""
    import json

    from fire_report.debrief import run_scenario_notes

    note = "open water at (1, 2) m (0.3 ha) left out: its widest disc (30 m) is narrower than a refill pass needs (60 m)"
    (tmp_path / "summary.json").write_text(json.dumps({"scenario_notes": [note]}))
    notes = run_scenario_notes(tmp_path / "bag")
    assert notes == [note]
    assert "left out: its widest disc (30 m)" in fire_types_html({"scenario_notes": notes})
    assert run_scenario_notes(tmp_path / "nothing" / "bag") == []
