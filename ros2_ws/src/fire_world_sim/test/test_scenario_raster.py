"""Scenario options of the raster fire: wind limit, fires burning before t = 0, shipped scenarios."""

from __future__ import annotations

from pathlib import Path

import pytest
from fire_uav_common.scenario import ScenarioError, load_scenario, scenario_from_dict
from fire_world_sim.fires import RasterFireModel, make_fire_model

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
MINIMAL = {"name": "m", "area": {"x_min_m": 0, "x_max_m": 1000, "y_min_m": 0, "y_max_m": 1000}}


def raster(**fields: object) -> dict:
    d = dict(MINIMAL)
    d["fires"] = {"model": "raster", "raster": fields}
    return d


def test_wind_limit_defaults_to_behave_and_is_parsed() -> None:
    assert scenario_from_dict(raster()).fires.raster.wind_limit == "behave"
    for v in ("behave", "andrews2013", "none"):
        assert scenario_from_dict(raster(wind_limit=v)).fires.raster.wind_limit == v


@pytest.mark.parametrize(
    ("fields", "match"),
    [
        (
            {"wind_limit": "rothermel"},
            r"fires\.raster\.wind_limit: must be one of \['behave', 'andrews2013', 'none'\]",
        ),
        ({"wind_limit": 3}, r"fires\.raster\.wind_limit: must be a non-empty string, got 3"),
        (
            {
                "wind": [{"start_s": -60, "speed_mps": 1, "direction_deg": 0}],
                "ignitions": [{"x_m": 10, "y_m": 10, "start_s": -120}],
            },
            r"fires\.raster\.wind\[0\]\.start_s: must be 0 or earlier: at or before the earliest ignition \(-120\)",
        ),
        (
            {
                "wind": [
                    {"start_s": -60, "speed_mps": 1, "direction_deg": 0},
                    {"start_s": -60, "speed_mps": 2, "direction_deg": 0},
                ]
            },
            r"fires\.raster\.wind\[1\]\.start_s: must be > the previous start_s \(-60\)",
        ),
    ],
)
def test_raster_option_errors(fields: dict, match: str) -> None:
    with pytest.raises(ScenarioError, match=match):
        scenario_from_dict(raster(**fields))


def test_negative_start_is_accepted_with_wind_from_before() -> None:
    s = scenario_from_dict(
        raster(
            wind=[{"start_s": -300, "speed_mps": 3, "direction_deg": 20}],
            ignitions=[{"x_m": 200, "y_m": 300, "start_s": -300}],
        )
    )
    assert s.fires.raster.ignitions[0].start_s == -300.0 and s.fires.raster.wind[0].start_s == -300.0
    # without a wind list the default calm wind starts with the earliest ignition
    s = scenario_from_dict(raster(ignitions=[{"x_m": 200, "y_m": 300, "start_s": -60}]))
    assert s.fires.raster.wind[0].start_s == -60.0


@pytest.mark.parametrize("name", ["grass_running", "grass_brush_hill"])
def test_shipped_scenarios_hand_over_a_burning_fire(name: str) -> None:
    s = load_scenario(SCENARIOS / f"{name}.yaml")
    assert min(ig.start_s for ig in s.fires.raster.ignitions) < 0
    assert s.mission.monitors_per_fire == 2 and s.uavs.count == 5
    m = make_fire_model(s.fires, s.terrain, s.lakes)
    assert isinstance(m, RasterFireModel)
    assert m.truth()[0].area_m2 > 1e4  # more than a hectare at t = 0
    assert m.step(0.0, 0.1) == [(0, "ignition")] and not m.all_out
