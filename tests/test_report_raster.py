"""The report's raster section on an in-memory mission: true perimeter from the fire grid, the PM
distance error against it, and the figures (grid + front + drops + Voronoi, burned area vs baseline)."""

from __future__ import annotations

import numpy as np
import pytest
from fire_report.data import RecordedEvent, RecordedMission
from fire_report.figures import fig_burned_area, fig_perimeter, fig_raster_front
from fire_report.metrics import perimeter_distance_error_raster, suppression_metrics, true_outer_distance
from fire_uav_common.constants import EventType, FireStatus

PLOT = {
    "name": "plot",
    "area": {"x_min_m": 0, "x_max_m": 200, "y_min_m": 0, "y_max_m": 200},
    "fires": {
        "model": "raster",
        "raster": {
            "cell_size_m": 5.0, "nx": 40, "ny": 40, "fuel_model": 1, "moisture": 0.06,
            "wind": [{"start_s": 0.0, "speed_mps": 3.0, "direction_deg": 0.0}],
            "ignitions": [{"x_m": 100.0, "y_m": 100.0, "start_s": 0.0}],
        },
    },
}  # fmt: skip


def disc_grid(t: float, r_m: float) -> dict:
    res, n = 5.0, 40
    c = (np.arange(n) + 0.5) * res
    xx, yy = np.meshgrid(c, c)
    d = np.hypot(xx - 100.0, yy - 100.0)
    data = np.zeros((n, n), dtype=np.int8)
    data[d <= r_m] = 60
    data[(d <= r_m) & (d > r_m - 5.0)] = 100
    return {"t": t, "origin": (0.0, 0.0), "resolution": res, "data": data}


def mission() -> RecordedMission:
    m = RecordedMission(
        path="mem", custom_data={"fire_uav.seed": "1"}, scenario=dict(PLOT), warnings=[], topics={}
    )
    m.fire_grids = [disc_grid(t, 30.0 + t / 10) for t in (0.0, 100.0, 200.0, 300.0)]
    bins = 36
    m.perimeters = {
        (0, 65536): {
            "t": np.array([100.0, 200.0]),
            "center": np.array([[100.0, 100.0], [100.0, 100.0]]),
            "outer": np.array([np.full(bins, 40.0 + 10.0), np.full(bins, 50.0 + 10.0)]),
        }
    }
    t = np.arange(0.0, 301.0, 1.0)
    m.truth_fires = {
        0: {"t": t, "area": 100.0 * np.minimum(t, 100.0), "status": np.full(t.size, FireStatus.ACTIVE)}
    }
    m.states = {0: {"t": t, "x": np.full(t.size, 60.0), "y": np.full(t.size, 60.0)},
                1: {"t": t, "x": np.full(t.size, 150.0), "y": np.full(t.size, 150.0)}}  # fmt: skip
    m.fronts = {
        0: [{"t": 50.0, "x": np.array([135.0]), "y": np.array([100.0]), "state": np.array([1], np.uint8)}]
    }
    m.world_events = [
        RecordedEvent(
            20.0,
            EventType.DROP,
            0,
            -1,
            0,
            135.0,
            100.0,
            2000.0,
            "hit fires [0], 10 of 40 cells burning",
            "world",
        ),
        RecordedEvent(
            40.0, EventType.DROP, 1, -1, -1, 10.0, 10.0, 2000.0, "missed, 0 of 40 cells burning", "world"
        ),
    ]
    m.t_last_s = 300.0
    return m


def test_true_outer_distance_of_a_disc_is_its_radius() -> None:
    d = true_outer_distance(disc_grid(0.0, 50.0), (100.0, 100.0), 36)
    assert np.all(np.abs(d - 50.0) <= 5.0)


def test_pm_distance_error_against_the_grid_is_the_offset_of_the_map() -> None:
    e = perimeter_distance_error_raster(mission(), 0, 65536)
    assert e["t"].tolist() == [100.0, 200.0]
    # the maximum over the angles: the 10 m offset, plus up to half a 5 m cell's diagonal (the hull
    # of the map's cell squares) and the sag between bins, less the raster disc's steps
    assert e["error_m"] == pytest.approx([10.0, 10.0], abs=6.0)
    assert np.all(e["floor_m"] <= 1.2 * 5.0)  # a raster disc: about a cell


def test_suppression_metrics_from_the_mission() -> None:
    s = suppression_metrics(mission())
    assert s["hit_rate"] == 0.5 and s["water_on_burning_kg"] == pytest.approx(500.0)
    assert s["burned_area_m2"] == 10000.0 and s["contained_at_s"] == 160.0  # grew until 100 s


def test_raster_figures_are_written(tmp_path) -> None:
    m = mission()
    names = [n for fn in (fig_raster_front, fig_perimeter) for n, _ in fn(m, tmp_path)]
    names[1:1] = [n for n, _ in fig_burned_area(m, tmp_path, baseline=mission())]
    assert names == ["raster_front.png", "burned_area.png", "perimeter.png"]
    assert all((tmp_path / n).stat().st_size > 10_000 for n in names)
