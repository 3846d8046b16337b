"""The report's ground on a landscape mission: fuel classes, hillshade, lat/lon, the maps.

Checked against what can be known without the code: Scott & Burgan's numbering of the 40 models
(the tens of ``code - 100`` name the family), the Lambertian reflectance of a tilted plane, the
latitude and longitude the mission summary gives for the same points (``geo_summary``), and a
mission without a landscape drawing nothing new.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from fire_report.data import RecordedEvent, RecordedMission
from fire_report.figures import fig_landscape, fig_raster_front, fig_tracks, fig_voronoi
from fire_report.ground import (
    FUEL_CLASSES,
    NON_BURNABLE,
    OUTSIDE,
    WATER,
    fuel_class,
    hillshade,
    mission_ground,
    places,
)
from fire_report.page import fires_html, places_html, render_page
from fire_report.report import with_latlon
from fire_uav_common.constants import EventType
from fire_uav_common.landscape import FBFM13_CODES, FBFM40_CODES, NONBURNABLE_CODES
from fire_uav_common.scenario import load_scenario
from fire_uav_common.scenario.ground import geo_summary

ROOT = Path(__file__).resolve().parents[1]
WORCESTER = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios" / "worcester_vt.yaml"
NAMES = [n for n, _ in FUEL_CLASSES]


# --- fuel classes -------------------------------------------------------------------------------
def test_each_of_the_40_models_falls_in_its_scott_burgan_family():
    families = ["grass", "grass-shrub", "shrub", "timber understory", "timber litter", "slash, blowdown"]
    for code in sorted(FBFM40_CODES - NONBURNABLE_CODES):
        want = families[(code - 100) // 20]  # GR 10x, GS 12x, SH 14x, TU 16x, TL 18x, SB 20x
        assert NAMES[fuel_class(np.array([code]))[0]] == want, code


def test_anderson_13_open_water_non_burnable_and_no_data():
    groups = {1: "grass", 2: "grass", 3: "grass", 4: "shrub", 7: "shrub", 8: "timber litter",
              10: "timber litter", 11: "slash, blowdown", 13: "slash, blowdown"}  # fmt: skip
    for code, want in groups.items():
        assert NAMES[fuel_class(np.array([code]))[0]] == want
    assert all(fuel_class(np.array([c]))[0] != OUTSIDE for c in FBFM13_CODES)
    nb = fuel_class(np.array(sorted(NONBURNABLE_CODES)))
    assert nb.tolist() == [NON_BURNABLE] * 7 + [WATER, NON_BURNABLE]  # 91..97, 98 water, 99
    assert fuel_class(np.array([0, 150, 205, 14])).tolist() == [OUTSIDE] * 4


# --- hillshade ----------------------------------------------------------------------------------
def _lambert(nx: float, ny: float) -> float:
    """cos(normal, sun) for a plane z = nx * east + ny * north, sun from azimuth 315, altitude 45."""
    sun = np.array([math.sin(math.radians(315)), math.cos(math.radians(315)), 1.0]) * math.sqrt(0.5)
    normal = np.array([-nx, -ny, 1.0]) / math.sqrt(1 + nx * nx + ny * ny)
    return float(np.clip(normal @ sun, 0, 1))


@pytest.mark.parametrize(
    ("rise_east", "rise_north"),
    [(0.3, 0.0), (-0.3, 0.0), (0.0, 0.3), (0.0, -0.3), (0.5, -0.5), (-0.8, 0.8)],
)
def test_hillshade_of_a_plane_is_its_lambertian_reflectance(rise_east, rise_north):
    cell = 30.0
    rows, cols = np.mgrid[0:12, 0:15]
    # north-up grid: row 0 is the northern edge, so north = -row
    elev = 400.0 + rise_east * cols * cell + rise_north * (-rows) * cell
    got = hillshade(elev, cell)
    assert np.allclose(got[2:-2, 2:-2], _lambert(rise_east, rise_north), atol=1e-6)


def test_a_slope_facing_the_sun_is_lighter_than_one_facing_away():
    cell = 30.0
    cols = np.tile(np.arange(20), (20, 1))
    elev = 400.0 + 20.0 * np.abs(cols - 10)  # a valley: west bank faces east, east bank faces west
    shade = hillshade(elev, cell)
    assert shade[10, 15] > shade[10, 5]  # the bank facing west (toward the north-west sun) is lit


# --- the ground of a recorded mission -----------------------------------------------------------
def _mission(scenario: dict, scenario_file: str = "") -> RecordedMission:
    custom = {"fire_uav.scenario_file": scenario_file} if scenario_file else {}
    return RecordedMission(path="mem", custom_data=custom, scenario=scenario, warnings=[], topics={})


@pytest.fixture(scope="module")
def worcester() -> dict:
    return yaml.safe_load(WORCESTER.read_text())


def test_the_ground_is_the_scenarios_window_and_its_lat_lon_the_summarys(worcester):
    ground, warning = mission_ground(_mission(worcester, str(WORCESTER)))
    assert warning is None and ground is not None
    assert ground.name == "worcester_vt"
    assert ground.extent == (0.0, 1500.0, 0.0, 1200.0) and ground.fuel.shape == (40, 50)
    assert ground.projected_origin == (1847865.0, 2602815.0)
    scenario = load_scenario(WORCESTER)
    geo = geo_summary(scenario)
    assert geo is not None
    for p in geo["ignitions"] + geo["uav_homes"]:
        lat, lon = ground.latlon(p["x_m"], p["y_m"])
        assert (round(float(lat), 6), round(float(lon), 6)) == (p["lat_deg"], p["lon_deg"])
    lat, lon = ground.latlon(750.0, 600.0)
    assert 44.3 < lat < 44.4 and -72.6 < lon < -72.5  # Worcester, Vermont
    # the pond the fleet refills at is open water on the drawn ground
    ((x, y, d),) = ground.lakes
    row, col = int((1200.0 - y) // ground.cell_m), int(x // ground.cell_m)
    assert d > 200 and fuel_class(ground.fuel)[row, col] == WATER


def test_the_ground_is_found_without_the_scenario_file_by_the_shipped_name(worcester):
    ground, warning = mission_ground(_mission(worcester, "/nonexistent/worcester_vt.yaml"))
    assert warning is None and ground is not None and ground.fuel.shape == (40, 50)


def test_no_landscape_no_ground_and_a_lost_landscape_is_one_warning(worcester):
    assert mission_ground(_mission({"name": "x", "fires": {"model": "analytic"}})) == (None, None)
    assert mission_ground(_mission({})) == (None, None)
    lost = yaml.safe_load(yaml.safe_dump(worcester))
    lost["fires"]["raster"]["landscape"]["source"] = "no_such_landscape"
    ground, warning = mission_ground(_mission(lost))
    assert ground is None and "no_such_landscape" in warning and "\n" not in warning


def _events(ground_mission: RecordedMission) -> RecordedMission:
    m = ground_mission
    m.truth_fires = {0: {"t": np.array([0.0, 10.0]), "x": np.array([285.0, 290.0]), "y": np.array([585.0, 585.0]),
                         "extent": np.array([50.0, 60.0]), "area": np.array([3e4, 3.3e4]),
                         "status": np.array([0, 0]), "drops": np.array([0, 1])}}  # fmt: skip
    m.truth_vehicles = {
        u: {"t": np.array([0.0, 5.0, 10.0]), "x": np.array([1000.0 + 30 * u, 800.0, 400.0]),
            "y": np.array([300.0, 450.0, 580.0]), "z": np.zeros(3), "yaw": np.zeros(3), "status": np.zeros(3), "step": np.arange(3)}
        for u in (0, 1)
    }  # fmt: skip
    m.states = {
        u: dict(v, P=np.zeros((3, 4, 4)), objective=np.zeros(3), lost=np.zeros(3))
        for u, v in m.truth_vehicles.items()
    }
    m.world_events = [
        RecordedEvent(4.0, int(EventType.DROP), 0, -1, 0, 300.0, 590.0, 1000.0, "", "world"),
        RecordedEvent(8.0, int(EventType.CRASH), 1, -1, -1, math.nan, math.nan, 0.0, "injected", "world"),
    ]
    data = np.zeros((40, 50), dtype=np.int8)
    data[18:22, 8:12] = 60
    data[19:21, 12] = 100
    m.fire_grids = [{"t": 10.0, "origin": (0.0, 0.0), "resolution": 30.0, "data": data}]
    return m


def test_places_give_every_position_in_degrees_as_the_summary_does(worcester):
    m = _events(_mission(worcester, str(WORCESTER)))
    ground, _ = mission_ground(m)
    assert ground is not None
    rows = places(m, ground)
    kinds = [r["kind"] for r in rows]
    assert kinds == ["ignition", "fire", "lake", "home", "home", "drop", "loss"]
    ign = geo_summary(load_scenario(WORCESTER))["ignitions"][0]  # type: ignore[index]
    assert (rows[0]["x_m"], rows[0]["y_m"], rows[0]["t_s"]) == (285.0, 585.0, -600.0)
    assert (rows[0]["lat_deg"], rows[0]["lon_deg"]) == (ign["lat_deg"], ign["lon_deg"])
    assert (rows[1]["lat_deg"], rows[1]["lon_deg"]) == (
        ign["lat_deg"],
        ign["lon_deg"],
    )  # fire 0 recorded there
    loss = rows[-1]
    assert (loss["x_m"], loss["y_m"]) == (800.0, 450.0)  # no crash position: where its truth was last
    html = places_html(rows, "worcester_vt")
    assert "worcester_vt" in html and f"{ign['lat_deg']:.6f}" in html and "UAV 1 lost" in html
    fires = with_latlon([{"fire": 0, "x_m": 285.0, "y_m": 585.0, "started_s": -600.0, "detected_s": None,
                          "detected_by": None, "drops": 1, "first_drop_s": 4.0, "out_s": None,
                          "burning_at_end": True}], ground)  # fmt: skip
    assert f"285, 585 ({ign['lat_deg']:.6f}, {ign['lon_deg']:.6f})" in fires_html(fires, raster=False)


def test_the_maps_of_a_landscape_mission_draw_the_ground(worcester, tmp_path):
    m = _events(_mission(worcester, str(WORCESTER)))
    ground, _ = mission_ground(m)
    assert [n for n, _ in fig_landscape(m, tmp_path, ground)] == ["landscape.png"]
    for fn in (fig_raster_front, fig_tracks, fig_voronoi):
        plain = tmp_path / "plain"
        plain.mkdir(exist_ok=True)
        ((name, cap),) = fn(m, tmp_path, ground)
        ((name0, cap0),) = fn(m, plain)
        assert name == name0
        assert (tmp_path / name).read_bytes() != (plain / name).read_bytes()  # the ground is drawn
    assert fig_landscape(m, tmp_path, None) == []  # no ground: the figures of today


def test_the_page_of_a_mission_without_a_landscape_has_no_places():
    kw = dict(entries=[], fires=[], uavs=[], faults=[], figures={}, sections=[], raster=False,
              collision_radius_m=None)  # fmt: skip
    plain = render_page({"outcome": "complete"}, {}, **kw)  # type: ignore[arg-type]
    assert plain == render_page({"outcome": "complete"}, {}, places=[], landscape=None, **kw)  # type: ignore[arg-type]
    assert "latitude" not in plain and 'id="places"' not in plain
    row = {
        "what": "fire 0",
        "t_s": 0.0,
        "x_m": 1.0,
        "y_m": 2.0,
        "lat_deg": 44.1,
        "lon_deg": -72.5,
        "kind": "fire",
    }
    geo = render_page({"outcome": "complete"}, {}, places=[row], landscape="worcester_vt", **kw)  # type: ignore[arg-type]
    assert 'id="places"' in geo and "WGS84" in geo
