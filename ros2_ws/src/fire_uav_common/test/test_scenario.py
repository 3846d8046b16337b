"""Tests of fire_uav_common.scenario: defaults, shipped files, every error path."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import yaml
from fire_uav_common.scenario import Scenario, ScenarioError, load_scenario, scenario_from_dict
from fire_uav_common.terrain import Lake, Terrain

SCENARIOS = Path(__file__).resolve().parents[2] / "fire_world_sim" / "scenarios"

# tall enough for the default fleet's starts (x = 50, y = 250 + 30 k, k < 5)
MINIMAL = {"name": "m", "area": {"x_min_m": 0, "x_max_m": 100, "y_min_m": 0, "y_max_m": 400}}


def write(tmp_path: Path, data: object, name: str = "s.yaml") -> Path:
    p = tmp_path / name
    p.write_text(yaml.safe_dump(data) if not isinstance(data, str) else data)
    return p


def with_(**sections: object) -> dict:
    d = dict(MINIMAL)
    d.update(sections)
    return d


def test_minimal_defaults(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, MINIMAL))
    assert isinstance(s, Scenario)
    assert s.area.x_max_m == 100.0 and s.area.width_m == 100.0 and s.area.height_m == 400.0
    assert s.seed == 0 and s.description == ""
    assert s.terrain == Terrain() and s.lakes == ()
    assert s.timing.control_period_s == 0.1 and s.timing.physics_period_s == 0.01
    assert s.timing.max_duration_s == 900.0 and s.timing.substeps == 10
    assert s.vehicle.v_stall_mps == 44.7 and s.vehicle.v_max_mps == 100.0
    assert s.vehicle.command_timeout_s == 3.0 and s.vehicle.water_capacity_kg == 2000.0
    assert s.uavs.count == 5 and s.uavs.takeoff_interval_s == 2.0
    assert s.sensors.gps.rate_hz == 10 and s.sensors.gps.sigma_m == 3.0 and s.sensors.gps.p_valid == 0.9
    assert s.sensors.altimeter.max_range_m == 40.0 and s.sensors.altimeter.p_valid == 0.8
    assert s.sensors.gyro.rate_hz == 100 and s.sensors.gyro.sigma_radps == 0.3
    assert s.sensors.fire.range_m == 70.0
    assert s.fires.model == "analytic" and s.fires.analytic == () and s.fires.raster is None
    assert s.comms.loss_probability == 0.05 and s.comms.outages == ()
    assert s.mission.crash_threshold_steps == 10 and s.mission.use_safety_band is True
    assert s.path.endswith("s.yaml")


def test_start_poses_follow_first_and_spacing(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, MINIMAL))
    poses = s.uav_start_poses()
    assert len(poses) == 5
    assert poses[0] == pytest.approx((50.0, 250.0, 0.0, -math.pi / 2))
    assert poses[4] == pytest.approx((50.0, 370.0, 0.0, -math.pi / 2))
    assert len(s.uav_start_poses(14)) == 14
    assert s.uav_start_poses(0) == []
    assert s.takeoff_time_s(3) == pytest.approx(6.0)


def test_documented_example_loads(tmp_path: Path) -> None:
    doc = (Path(__file__).resolve().parents[4] / "docs" / "scenario.md").read_text()
    example = doc.split("```yaml")[1].split("```")[0]
    s = load_scenario(write(tmp_path, example))
    assert s.name == "ff_two_fires"
    assert s.lakes == (Lake(50.0, 50.0, 90.0),)
    assert s.terrain.hills[0].height_m == 20.0
    assert s.fires.raster is not None and s.fires.raster.fuel_patches[0].fuel_model == 5
    assert s.fires.raster.wind[0].direction_deg == 90.0
    assert s.comms.outages[0].from_id == 0 and s.comms.outages[0].to_id == 1


@pytest.mark.parametrize("path", sorted(SCENARIOS.glob("*.yaml")), ids=lambda p: p.name)
def test_shipped_scenarios_load(path: Path) -> None:
    s = load_scenario(path)
    assert s.name == path.stem


def test_overrides(tmp_path: Path) -> None:
    s = load_scenario(
        write(tmp_path, MINIMAL), overrides={"seed": 7, "uavs.count": 3, "comms.loss_probability": 0}
    )
    assert s.seed == 7 and s.uavs.count == 3 and s.comms.loss_probability == 0.0
    with pytest.raises(ScenarioError, match=r"s\.yaml: uavs\.count: must be >= 1, got 0"):
        load_scenario(write(tmp_path, MINIMAL), overrides={"uavs.count": 0})


def test_from_dict_names_dict() -> None:
    with pytest.raises(ScenarioError, match=r"^<dict>: name: required field missing"):
        scenario_from_dict({"area": MINIMAL["area"]})


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ({"area": MINIMAL["area"]}, r"s\.yaml: name: required field missing"),
        ({"name": "x"}, r"s\.yaml: area: required field missing"),
        (with_(bogus=1), r"s\.yaml: bogus: unknown field"),
        (with_(area={"x_min_m": 0, "x_max_m": 10, "y_min_m": 0}), r"area\.y_max_m: required field missing"),
        (
            with_(area={"x_min_m": 5, "x_max_m": 1, "y_min_m": 0, "y_max_m": 1}),
            r"area\.x_max_m: must be > x_min_m",
        ),
        (
            with_(area={"x_min_m": "a", "x_max_m": 1, "y_min_m": 0, "y_max_m": 1}),
            r"area\.x_min_m: must be a number",
        ),
        (with_(area=[1, 2]), r"area: must be a mapping, got list"),
        (with_(seed=-1), r"seed: must be >= 0, got -1"),
        (with_(seed=1.5), r"seed: must be an integer"),
        (
            with_(terrain={"hills": [{"x_m": 0, "y_m": 0, "height_m": 1, "sigma_m": 0}]}),
            r"terrain\.hills\[0\]\.sigma_m: must be > 0",
        ),
        (with_(terrain={"slope": 1}), r"terrain\.slope: unknown field"),
        (
            with_(lakes=[{"x_m": 0, "y_m": 0, "diameter_m": -3}]),
            r"lakes\[0\]\.diameter_m: must be > 0, got -3",
        ),
        (with_(lakes={"x_m": 0}), r"lakes: must be a list"),
        (with_(timing={"physics_period_s": 0.03}), r"timing\.physics_period_s: must divide control_period_s"),
        (with_(timing={"control_period_s": 0}), r"timing\.control_period_s: must be > 0"),
        (with_(vehicle={"v_max_mps": 40}), r"vehicle\.v_max_mps: must be > v_stall_mps"),
        (with_(vehicle={"water_capacity_kg": 0}), r"vehicle\.water_capacity_kg: must be > 0"),
        (with_(vehicle={"v_stal_mps": 40}), r"vehicle\.v_stal_mps: unknown field"),
        (with_(uavs={"count": 0}), r"uavs\.count: must be >= 1"),
        (with_(uavs={"count": 300}), r"uavs\.count: must be <= 255"),
        (with_(uavs={"first": {"x": 1}}), r"uavs\.first\.x: unknown field"),
        (with_(sensors={"gps": {"p_valid": 1.5}}), r"sensors\.gps\.p_valid: must be <= 1, got 1\.5"),
        (with_(sensors={"gyro": {"rate_hz": 0}}), r"sensors\.gyro\.rate_hz: must be > 0"),
        (with_(sensors={"lidar": {}}), r"sensors\.lidar: unknown field"),
        (
            with_(fires={"model": "cellular"}),
            r"fires\.model: must be one of \['analytic', 'raster'\], got 'cellular'",
        ),
        (
            with_(
                fires={"analytic": [{"x_m": 1, "y_m": 1, "sigma_m": 5}, {"x_m": 1, "y_m": 1, "sigma_m": -3}]}
            ),
            r"s\.yaml: fires\.analytic\[1\]\.sigma_m: must be > 0, got -3",
        ),
        (
            with_(fires={"analytic": [{"x_m": 1, "sigma_m": 5}]}),
            r"fires\.analytic\[0\]\.y_m: required field missing",
        ),
        (
            with_(fires={"analytic": [{"x_m": 1, "y_m": 1, "sigma_m": 5, "vz_mps": 1}]}),
            r"fires\.analytic\[0\]\.vz_mps: unknown field",
        ),
        (with_(fires={"model": "raster"}), r"fires\.raster: required when fires\.model is 'raster'"),
        (
            with_(fires={"model": "raster", "raster": {"fuel_model": 14}}),
            r"fires\.raster\.fuel_model: must be one of",
        ),
        (
            with_(fires={"model": "raster", "raster": {"moisture": 0.9}}),
            r"fires\.raster\.moisture: must be <= 0\.6",
        ),
        (with_(fires={"model": "raster", "raster": {"nx": 2}}), r"fires\.raster\.nx: must be >= 3"),
        (
            with_(
                fires={
                    "model": "raster",
                    "raster": {"wind": [{"start_s": 5, "speed_mps": 1, "direction_deg": 0}]},
                }
            ),
            r"fires\.raster\.wind\[0\]\.start_s: must be 0",
        ),
        (
            with_(
                fires={
                    "model": "raster",
                    "raster": {
                        "wind": [
                            {"speed_mps": 1, "direction_deg": 0},
                            {"start_s": 0, "speed_mps": 1, "direction_deg": 0},
                        ]
                    },
                }
            ),
            r"fires\.raster\.wind\[1\]\.start_s: must be > the previous",
        ),
        (
            with_(fires={"model": "raster", "raster": {"wind": [{"speed_mps": -1, "direction_deg": 0}]}}),
            r"fires\.raster\.wind\[0\]\.speed_mps: must be >= 0",
        ),
        (
            with_(fires={"model": "raster", "raster": {"ignitions": [{"x_m": 5000, "y_m": 1}]}}),
            r"fires\.raster\.ignitions\[0\]: \(5000, 1\) is outside the raster grid",
        ),
        (
            with_(
                fires={
                    "model": "raster",
                    "raster": {
                        "fuel_patches": [
                            {"x_min_m": 5, "x_max_m": 1, "y_min_m": 0, "y_max_m": 1, "fuel_model": 1}
                        ]
                    },
                }
            ),
            r"fires\.raster\.fuel_patches\[0\]: must have x_max_m > x_min_m",
        ),
        (with_(comms={"loss_probability": 2}), r"comms\.loss_probability: must be <= 1"),
        (
            with_(comms={"outages": [{"from": 0, "to": 0, "start_s": 1, "end_s": 2}]}),
            r"comms\.outages\[0\]\.to: must differ",
        ),
        (
            with_(comms={"outages": [{"from": 0, "to": 1, "start_s": 3, "end_s": 2}]}),
            r"comms\.outages\[0\]\.end_s: must be > start_s",
        ),
        (
            with_(uavs={"count": 3}, comms={"outages": [{"from": 0, "to": 3, "start_s": 1, "end_s": 2}]}),
            r"comms\.outages\[0\]\.to: UAV 3 does not exist: the fleet has ids 0\.\.2",
        ),
        (
            with_(uavs={"count": 2}, comms={"outages": [{"from": 7, "to": 1, "start_s": 1, "end_s": 2}]}),
            r"comms\.outages\[0\]\.from: UAV 7 does not exist",
        ),
        (with_(mission={"use_safety_band": "yes"}), r"mission\.use_safety_band: must be true or false"),
        (with_(mission={"crash_threshold_steps": 0}), r"mission\.crash_threshold_steps: must be >= 1"),
        (
            with_(area={"x_min_m": float("nan"), "x_max_m": 1, "y_min_m": 0, "y_max_m": 1}),
            r"area\.x_min_m: must be finite",
        ),
    ],
)
def test_errors_name_file_and_field(tmp_path: Path, data: dict, match: str) -> None:
    with pytest.raises(ScenarioError, match=match):
        load_scenario(write(tmp_path, data))


def test_file_errors(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match=r"nope\.yaml: file not found"):
        load_scenario(tmp_path / "nope.yaml")
    with pytest.raises(ScenarioError, match=r"is a directory"):
        load_scenario(tmp_path)
    with pytest.raises(ScenarioError, match=r"s\.yaml: invalid YAML"):
        load_scenario(write(tmp_path, "name: [unclosed\n"))
    with pytest.raises(ScenarioError, match=r"s\.yaml: file is empty"):
        load_scenario(write(tmp_path, ""))
    with pytest.raises(ScenarioError, match=r"s\.yaml: top level must be a mapping, got list"):
        load_scenario(write(tmp_path, "- 1\n- 2\n"))


def test_scenario_error_is_value_error() -> None:
    assert issubclass(ScenarioError, ValueError)


def test_dataclasses_are_frozen(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, MINIMAL))
    with pytest.raises(AttributeError):
        s.seed = 3  # type: ignore[misc]
    with pytest.raises(AttributeError):
        s.area.x_min_m = 3  # type: ignore[misc]


def test_mission_tactic_auto_by_default_flank_on_request_and_a_clear_error(tmp_path: Path) -> None:
    assert (
        load_scenario(write(tmp_path, MINIMAL)).mission.tactic == "auto"
    )  # docs/studies.md, the 900 s study
    s = load_scenario(write(tmp_path, with_(mission={"tactic": "flank"})))
    assert s.mission.tactic == "flank"
    with pytest.raises(
        ScenarioError,
        match=r"s\.yaml: mission\.tactic: must be one of \['head', 'flank', 'auto'\], got 'tail'",
    ):
        load_scenario(write(tmp_path, with_(mission={"tactic": "tail"})))


def test_prior_fires_mode_is_validated_and_defaults_to_unknown():
    from fire_uav_common.scenario import ScenarioError, scenario_from_dict

    base = {"name": "x", "area": {"x_min_m": 0, "x_max_m": 100, "y_min_m": 0, "y_max_m": 400}}
    assert scenario_from_dict(base).mission.prior_fires == "unknown"
    assert scenario_from_dict({**base, "mission": {"prior_fires": "known"}}).mission.prior_fires == "known"
    with pytest.raises(
        ScenarioError, match=r"mission\.prior_fires: must be one of \['unknown', 'known'\], got 'maybe'"
    ):
        scenario_from_dict({**base, "mission": {"prior_fires": "maybe"}})
    with pytest.raises(ScenarioError, match=r"mission\.prior_position_sigma_m: must be >= 0"):
        scenario_from_dict({**base, "mission": {"prior_position_sigma_m": -1}})


def test_known_fires_are_refused_on_a_raster_fire():
    """The dispatch briefing holds analytic fires only, and agents told their fires are known do
    not search: 'known' on a raster fire would leave the fleet nothing to find the fire by."""
    with pytest.raises(
        ScenarioError,
        match=r"grass_running\.yaml: mission\.prior_fires: 'known' briefs analytic fires only, got fires\.model 'raster'",
    ):
        load_scenario(SCENARIOS / "grass_running.yaml", overrides={"mission.prior_fires": "known"})
    assert load_scenario(SCENARIOS / "ff_two_fires.yaml", overrides={"mission.prior_fires": "known"})


def test_lake_sequence_is_off_by_default_stack_on_request_and_a_clear_error():
    from fire_uav_common.scenario import ScenarioError, scenario_from_dict

    base = {"name": "x", "area": {"x_min_m": 0, "x_max_m": 100, "y_min_m": 0, "y_max_m": 400}}
    assert scenario_from_dict(base).mission.lake_sequence == "none"  # opt-in (docs/airframes.md)
    stack = scenario_from_dict({**base, "mission": {"lake_sequence": "stack"}})
    assert stack.mission.lake_sequence == "stack"
    with pytest.raises(
        ScenarioError, match=r"mission\.lake_sequence: must be one of \['none', 'stack'\], got 'on'"
    ):
        scenario_from_dict({**base, "mission": {"lake_sequence": "on"}})


def test_post_search_s_defaults_to_the_agents_45_s_and_a_negative_one_is_a_clear_error():
    from fire_uav_common.scenario import ScenarioError, scenario_from_dict

    base = {"name": "x", "area": {"x_min_m": 0, "x_max_m": 100, "y_min_m": 0, "y_max_m": 400}}
    assert scenario_from_dict(base).mission.post_search_s == 45.0  # fire_uav_agent.mission's default
    assert scenario_from_dict({**base, "mission": {"post_search_s": 150}}).mission.post_search_s == 150.0
    with pytest.raises(ScenarioError, match=r"mission\.post_search_s: must be >= 0"):
        scenario_from_dict({**base, "mission": {"post_search_s": -1}})


def test_outage_ids_are_checked_against_the_fleet_actually_flown(tmp_path: Path) -> None:
    """A scenario valid for uavs.count 4 names a UAV a 3-UAV fleet (the runner's --uavs 3) lacks."""
    from fire_uav_common.scenario import check_fleet_size

    outages = [{"from": 0, "to": 1, "start_s": 1, "end_s": 2}, {"from": 2, "to": 3, "start_s": 1, "end_s": 2}]
    s = load_scenario(write(tmp_path, with_(uavs={"count": 4}, comms={"outages": outages})))
    check_fleet_size(s, 4)
    with pytest.raises(
        ScenarioError,
        match=r"s\.yaml: comms\.outages\[1\]\.to: UAV 3 does not exist: the fleet has ids 0\.\.2$",
    ):
        check_fleet_size(s, 3)


FF_TWO_FIRES = SCENARIOS / "ff_two_fires.yaml"


@pytest.mark.parametrize(
    ("overrides", "pattern"),
    [
        # the analytic fire at x = 3000 m in ff_two_fires' 600 m area: no UAV could ever find it
        (
            {"fires.analytic": [{"x_m": 3000.0, "y_m": 400.0, "sigma_m": 50.0}]},
            r"ff_two_fires\.yaml: fires\.analytic\[0\]: fire centre \(3000, 400\) m is outside the area "
            r"x 0\.\.600, y 0\.\.600 m$",
        ),
        (
            {"lakes": [{"x_m": 50.0, "y_m": -100.0, "diameter_m": 90.0}]},
            r": lakes\[0\]: lake centre \(50, -100\) m is outside",
        ),
        (
            {"uavs.first": {"x_m": 700.0, "y_m": 250.0}},
            r": uavs\.first: UAV 0 starts at \(700, 250\) m is outside",
        ),
        # the fifth UAV of the line: 250 + 4 x 100 = 650 m
        (
            {"uavs.spacing": {"dx_m": 0.0, "dy_m": 100.0}},
            r": uavs\.spacing: UAV 4 starts at \(50, 650\) m is outside",
        ),
    ],
)
def test_positions_outside_the_area_are_named(overrides: dict, pattern: str) -> None:
    with pytest.raises(ScenarioError, match=pattern):
        load_scenario(FF_TWO_FIRES, overrides=overrides)


def test_raster_ignition_outside_the_area_or_in_a_lake_is_named(tmp_path: Path) -> None:
    area = {"x_min_m": 0, "x_max_m": 400, "y_min_m": 0, "y_max_m": 400}
    raster = {"cell_size_m": 5.0, "nx": 200, "ny": 200, "ignitions": [{"x_m": 900.0, "y_m": 300.0}]}
    d = {"name": "r", "area": area, "fires": {"model": "raster", "raster": raster}}
    # inside the raster grid (0..1000 m), outside the area (0..400 m)
    with pytest.raises(
        ScenarioError, match=r"fires\.raster\.ignitions\[0\]: ignition \(900, 300\) m is outside the area"
    ):
        load_scenario(write(tmp_path, d))
    raster["ignitions"] = [{"x_m": 110.0, "y_m": 95.0}]
    d["lakes"] = [{"x_m": 100.0, "y_m": 100.0, "diameter_m": 40.0}]
    with pytest.raises(
        ScenarioError,
        match=r"fires\.raster\.ignitions\[0\]: ignition \(110, 95\) m is in lakes\[0\]: a non-burnable cell",
    ):
        load_scenario(write(tmp_path, d))
    raster["ignitions"] = [{"x_m": 130.0, "y_m": 95.0}]  # just outside the lake's 20 m radius
    assert load_scenario(write(tmp_path, d)).fires.raster is not None


def test_every_shipped_scenario_places_everything_inside_its_area() -> None:
    for f in sorted(SCENARIOS.glob("*.yaml")):
        s = load_scenario(f)
        for x, y, _, _ in s.uav_start_poses():
            assert s.area.contains(x, y), f.name
