"""A scenario on real ground (fires.raster.landscape): grid, terrain, lakes and bad input."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from fire_uav_common.landscape import load_landscape
from fire_uav_common.scenario import ScenarioError, load_scenario
from fire_uav_common.terrain import GridTerrain

ROOT = Path(__file__).resolve().parents[4]
SCENARIO = ROOT / "ros2_ws" / "src" / "fire_world_sim" / "scenarios" / "worcester_vt.yaml"
LANDSCAPE = ROOT / "data" / "landscapes" / "worcester_vt"


@pytest.fixture(scope="module")
def scenario():
    return load_scenario(SCENARIO)


@pytest.fixture(scope="module")
def full():
    return load_landscape(LANDSCAPE)


def test_the_grid_is_the_window_snapped_to_the_landscapes_cells(scenario, full) -> None:
    r = scenario.fires.raster
    assert (r.cell_size_m, r.nx, r.ny) == (30.0, 50, 40)
    ox, oy = r.landscape.projected_origin
    # the window's south-west corner, moved to a cell edge of the full raster
    x0, _, _, y1 = full.bounds
    assert (ox - x0) % 30.0 == 0 and (y1 - oy) % 30.0 == 0
    assert abs(ox - 1847865.0) < 30.0 and abs(oy - 2602815.0) < 30.0


def test_terrain_is_the_elevation_layer_at_every_cell_centre(scenario, full) -> None:
    t = scenario.terrain
    assert isinstance(t, GridTerrain)
    ox, oy = scenario.fires.raster.landscape.projected_origin
    rng = np.random.default_rng(0)
    for _ in range(20):
        x, y = rng.uniform(15.0, 1480.0), rng.uniform(15.0, 1180.0)
        x, y = (np.floor(x / 30.0) + 0.5) * 30.0, (np.floor(y / 30.0) + 0.5) * 30.0  # a cell centre
        row, col = full.cell_of(x + ox, y + oy)
        if full.has_data[row, col]:
            assert t.elevation(x, y) == pytest.approx(full.elevation_m[row, col])
    # between two centres: linear
    e1, e2 = t.elevation(45.0, 45.0), t.elevation(75.0, 45.0)
    assert t.elevation(60.0, 45.0) == pytest.approx(0.5 * (e1 + e2))


def test_the_pond_is_a_lake_whose_disc_is_all_water(scenario, full) -> None:
    ox, oy = scenario.fires.raster.landscape.projected_origin
    assert len(scenario.lakes) == 1
    lake = scenario.lakes[0]
    assert lake.diameter_m >= 200.0
    xs, ys = full.cell_center(*np.indices(full.shape))
    inside = (xs - ox - lake.x_m) ** 2 + (ys - oy - lake.y_m) ** 2 <= (lake.diameter_m / 2) ** 2
    assert inside.sum() > 30 and np.all(full.fuel[inside] == 98)
    assert scenario.notes == ()


def test_the_pond_is_over_water_exactly_on_its_water_cells(scenario, full) -> None:
    """The refill check reads the outline: every cell centre of the window is over the lake iff
    its fuel is open water (98), including the water outside the disc."""
    ox, oy = scenario.fires.raster.landscape.projected_origin
    lake = scenario.lakes[0]
    r = scenario.fires.raster
    xs = (np.arange(r.nx) + 0.5) * r.cell_size_m
    ys = (np.arange(r.ny) + 0.5) * r.cell_size_m
    disc_only = 0
    for y in ys:
        for x in xs:
            row, col = full.cell_of(x + ox, y + oy)
            assert lake.contains(x, y) == (full.fuel[row, col] == 98), (x, y)
            disc = math.hypot(x - lake.x_m, y - lake.y_m) <= lake.diameter_m / 2
            disc_only += int(lake.contains(x, y) and not disc)
    assert disc_only > 10  # the outline holds water the disc leaves out
    assert lake.water is not None and lake.water.area_m2 == pytest.approx(
        900.0 * sum(full.fuel[full.cell_of(x + ox, y + oy)] == 98 for x in xs for y in ys)
    )


def test_the_ponds_longest_straight_run_is_over_water_and_longer_than_the_disc(scenario) -> None:
    lake = scenario.lakes[0]
    run = lake.longest_run
    assert lake.diameter_m < run.length_m
    assert run.length_m == pytest.approx(math.hypot(run.x1_m - run.x0_m, run.y1_m - run.y0_m))
    for f in np.linspace(0.0, 1.0, 200):  # every point of the segment is over water
        assert lake.contains(run.x0_m + f * (run.x1_m - run.x0_m), run.y0_m + f * (run.y1_m - run.y0_m))


def test_the_ponds_outline_polygon_encloses_its_area(scenario) -> None:
    lake = scenario.lakes[0]
    assert lake.water is not None
    rings = lake.water.outline()
    area = 0.0
    for poly in rings:
        for k, ring in enumerate(poly):
            x, y = np.array(ring).T
            a = 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))  # shoelace
            area += a if k == 0 else -a
    assert area == pytest.approx(lake.water.area_m2)


def test_water_too_narrow_for_a_refill_pass_is_left_out_with_a_note() -> None:
    s = load_scenario(SCENARIO, overrides={"fires.raster.landscape.min_lake_diameter_m": 300.0})
    assert s.lakes == ()
    (note,) = s.notes
    assert "its widest disc (270 m) is narrower than a refill pass needs (300 m)" in note


def _with(tmp_path: Path, **raster_edits: object) -> Path:
    d = yaml.safe_load(SCENARIO.read_text())
    for k, v in raster_edits.items():
        if v is None:
            d["fires"]["raster"].pop(k, None)
        else:
            d["fires"]["raster"][k] = v
    p = tmp_path / "w.yaml"
    p.write_text(yaml.safe_dump(d))
    return p


@pytest.mark.parametrize(
    ("edits", "pattern"),
    [
        # the pond's centre: open water
        (
            {"ignitions": [{"x_m": 1305.0, "y_m": 645.0}]},
            r"w\.yaml: fires\.raster\.ignitions\[0\]: .*non-burnable fuel code 98",
        ),
        (
            {
                "landscape": {
                    "source": "worcester_vt",
                    "window": {"x_min_m": 0, "y_min_m": 0, "x_max_m": 10, "y_max_m": 10},
                }
            },
            r"w\.yaml: fires\.raster\.landscape: .*window .* lies outside the raster bounds",
        ),
        (
            {"landscape": {"source": "no_such_place"}},
            r"fires\.raster\.landscape\.source: 'no_such_place' is neither",
        ),
        ({"nx": 10}, r"fires\.raster\.nx: set by fires\.raster\.landscape: remove it"),
        (
            {"landscape": {"source": "worcester_vt", "crown": "rothermel"}},
            r"fires\.raster\.landscape\.crown: must be one of",
        ),
        (
            {"landscape": {"source": "worcester_vt", "moisture": {"m_1h": 0}}},
            r"fires\.raster\.landscape\.moisture\.m_1h: must be > 0",
        ),
    ],
)
def test_bad_landscape_input_names_the_field(tmp_path: Path, edits: dict, pattern: str) -> None:
    with pytest.raises(ScenarioError, match=pattern):
        load_scenario(_with(tmp_path, **edits))


def test_ignition_outside_the_window_names_the_ignition(tmp_path: Path) -> None:
    # inside the area (widened) but beyond the window's 1500 m
    p = _with(tmp_path, ignitions=[{"x_m": 1600.0, "y_m": 585.0}])
    with pytest.raises(ScenarioError, match=r"fires\.raster\.ignitions\[0\]: .*outside the landscape"):
        load_scenario(p, overrides={"area.x_max_m": 2000.0})


def test_a_terrain_section_beside_a_landscape_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match=r"w\.yaml: terrain: set by fires\.raster\.landscape"):
        load_scenario(_with(tmp_path), overrides={"terrain": {"base_m": 100.0}})


def test_a_path_relative_to_the_scenario_file_works(tmp_path: Path) -> None:
    sub = tmp_path / "sub"
    sub.mkdir()
    d = yaml.safe_load(SCENARIO.read_text())
    d["fires"]["raster"]["landscape"]["source"] = str(
        Path(*[".."] * len(sub.parts)) / LANDSCAPE.relative_to("/")
    )
    (sub / "s.yaml").write_text(yaml.safe_dump(d))
    s = load_scenario(sub / "s.yaml")
    assert s.fires.raster.landscape.source == str(LANDSCAPE.resolve())


def test_geo_summary_gives_worcester_in_degrees(scenario) -> None:
    from fire_uav_common.scenario.ground import geo_summary

    g = geo_summary(scenario)
    assert g is not None and len(g["ignitions"]) == 1 and len(g["uav_homes"]) == scenario.uavs.count
    ig = g["ignitions"][0]
    # Worcester, Vermont: about 44.37 N, 72.55 W; the window is ~3.7 km wide
    assert 44.3 < ig["lat_deg"] < 44.45 and -72.6 < ig["lon_deg"] < -72.45
    home = g["uav_homes"][0]
    # the distance on the sphere (haversine) is the map distance: Albers' scale is ~1 here
    p1, p2 = math.radians(ig["lat_deg"]), math.radians(home["lat_deg"])
    dl = math.radians(home["lon_deg"] - ig["lon_deg"])
    h = math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    sphere_m = 2 * 6371008.8 * math.asin(math.sqrt(h))
    assert sphere_m == pytest.approx(math.hypot(home["x_m"] - ig["x_m"], home["y_m"] - ig["y_m"]), rel=0.01)
    assert geo_summary(load_scenario(SCENARIO.parent / "grass_running.yaml")) is None
