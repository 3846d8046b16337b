"""The scenario's section readers (fire_uav_common.scenario.sections), field by field.

Truth: docs/scenario.md (each field, its default and its bounds) and the error format of
docs/scenario.md ("FILE: dotted.field: message", exit status 2 in the CLIs). Each section is read
with every field set to a value no default has, so a field read from the wrong key or left at its
default shows; each bound is tried on both sides of its edge, with the message whole. Fast
(~0.1 s): the mutation selection of ``fire_uav_common.scenario.sections`` runs it once per mutant.
"""

from __future__ import annotations

import re

import pytest
from fire_uav_common.scenario import ScenarioError, scenario_from_dict
from fire_uav_common.scenario import types as t
from fire_uav_common.terrain import Hill, Lake

AREA = {"x_min_m": -10, "x_max_m": 100, "y_min_m": 5, "y_max_m": 400}


def _load(**sections):
    return scenario_from_dict({"name": "s", "area": AREA, **sections})


def _refused(message: str, **sections) -> None:
    with pytest.raises(ScenarioError, match="^" + re.escape(f"<dict>: {message}") + "$"):
        _load(**sections)


# --- mission ---------------------------------------------------------------------------------------
MISSION = {
    "crash_threshold_steps": 3,
    "grid_resolution_m": 2.5,
    "sigma_water_m": 33.0,
    "sigma_landing_m": 7.0,
    "use_safety_band": False,
    "safety_radius_m": 0,
    "monitors_per_fire": 2,
    "search_first": True,
    "tactic": "flank",
    "prior_fires": "known",
    "prior_position_sigma_m": 0,
    "prior_extent_sigma_fraction": 1,
    "lake_sequence": "stack",
    "post_search_s": 0,
    "post_search_max_s": 20,
    "vertical_band": "predicted",
}


def test_every_mission_field_is_read_from_its_own_key():
    m = _load(mission=MISSION).mission
    assert m == t.MissionSettings(**MISSION)
    assert all(type(getattr(m, k)) is type(getattr(t.MissionSettings(), k)) for k in MISSION)


@pytest.mark.parametrize("key", sorted(MISSION))
def test_a_mission_field_alone_leaves_the_others_at_their_defaults(key):
    m = _load(mission={key: MISSION[key]}).mission
    for other in MISSION:
        want = MISSION[key] if other == key else getattr(t.MissionSettings(), other)
        assert getattr(m, other) == want, other
    assert _load().mission == t.MissionSettings() == _load(mission=None).mission


@pytest.mark.parametrize(
    ("key", "value", "message"),
    [
        ("crash_threshold_steps", 0, "must be >= 1, got 0"),
        ("grid_resolution_m", 0, "must be > 0, got 0"),
        ("sigma_water_m", 0, "must be > 0, got 0"),
        ("sigma_landing_m", 0, "must be > 0, got 0"),
        ("safety_radius_m", -0.5, "must be >= 0, got -0.5"),
        ("monitors_per_fire", -1, "must be >= 0, got -1"),
        ("prior_position_sigma_m", -0.5, "must be >= 0, got -0.5"),
        ("prior_extent_sigma_fraction", -0.5, "must be >= 0, got -0.5"),
        ("prior_extent_sigma_fraction", 1.5, "must be <= 1, got 1.5"),
        ("post_search_s", -0.5, "must be >= 0, got -0.5"),
        ("post_search_max_s", -0.5, "must be >= 0, got -0.5"),
        ("use_safety_band", 1, "must be true or false, got 1"),
        ("search_first", "yes", "must be true or false, got 'yes'"),
        ("tactic", "x", "must be one of ['head', 'flank', 'auto'], got 'x'"),
        ("prior_fires", "x", "must be one of ['unknown', 'known'], got 'x'"),
        ("lake_sequence", "x", "must be one of ['none', 'stack'], got 'x'"),
        ("vertical_band", "x", "must be one of ['auto', 'now', 'predicted'], got 'x'"),
    ],
)
def test_each_mission_bound_is_named(key, value, message):
    _refused(f"mission.{key}: {message}", mission={key: value})


def test_the_mission_bounds_themselves_are_valid():
    m = _load(
        mission={"crash_threshold_steps": 1, "monitors_per_fire": 0, "prior_extent_sigma_fraction": 0}
    ).mission
    assert (m.crash_threshold_steps, m.monitors_per_fire, m.prior_extent_sigma_fraction) == (1, 0, 0.0)
    _refused("mission.nope: unknown field; expected one of " + str(sorted(MISSION)), mission={"nope": 1})


# --- comms ----------------------------------------------------------------------------------------
def test_comms_outages_are_read_in_order():
    c = _load(
        uavs={"count": 3},
        comms={
            "loss_probability": 0.25,
            "outages": [
                {"from": 2, "to": 0, "start_s": 0, "end_s": 4.5},
                {"from": 0, "to": 1, "start_s": 3, "end_s": 9},
            ],
        },
    ).comms
    assert c == t.Comms(0.25, (t.LinkOutage(2, 0, 0.0, 4.5), t.LinkOutage(0, 1, 3.0, 9.0)))
    assert _load().comms == t.Comms()
    for p in (0, 1):
        assert _load(comms={"loss_probability": p}).comms.loss_probability == p


@pytest.mark.parametrize(
    ("outage", "message"),
    [
        (
            {"from": 0, "to": 1, "start_s": 5, "end_s": 5},
            "comms.outages[1].end_s: must be > start_s (5), got 5",
        ),
        ({"from": 1, "to": 1, "start_s": 0, "end_s": 5}, "comms.outages[1].to: must differ from 'from' (1)"),
        (
            {"from": 3, "to": 1, "start_s": 0, "end_s": 5},
            "comms.outages[1].from: UAV 3 does not exist: the fleet has ids 0..2",
        ),
        (
            {"from": 1, "to": 3, "start_s": 0, "end_s": 5},
            "comms.outages[1].to: UAV 3 does not exist: the fleet has ids 0..2",
        ),
        ({"from": -1, "to": 1, "start_s": 0, "end_s": 5}, "comms.outages[1].from: must be >= 0, got -1"),
        ({"from": 0, "to": -1, "start_s": 0, "end_s": 5}, "comms.outages[1].to: must be >= 0, got -1"),
        ({"from": 0, "to": 1, "start_s": -1, "end_s": 5}, "comms.outages[1].start_s: must be >= 0, got -1"),
        ({"from": 0, "to": 1, "start_s": 0}, "comms.outages[1].end_s: required field missing"),
    ],
)
def test_a_bad_outage_is_named_by_its_index_and_field(outage, message):
    good = {"from": 0, "to": 2, "start_s": 0, "end_s": 1}
    _refused(message, uavs={"count": 3}, comms={"outages": [good, outage]})


@pytest.mark.parametrize("p", [-0.01, 1.01])
def test_a_loss_probability_outside_0_1_is_named(p):
    bound = ">= 0" if p < 0 else "<= 1"
    _refused(f"comms.loss_probability: must be {bound}, got {p:g}", comms={"loss_probability": p})


# --- uavs, area, timing, vehicle ------------------------------------------------------------------
def test_the_fleet_is_read_from_its_keys():
    u = _load(
        uavs={
            "count": 255,
            "first": {"x_m": 1.5, "y_m": 12.5, "z_m": 3.0, "yaw_rad": 0.25},
            "spacing": {"dx_m": 0.25, "dy_m": 1.5},
            "takeoff_interval_s": 0,
        }
    ).uavs
    assert u == t.Uavs(255, t.Pose(1.5, 12.5, 3.0, 0.25), t.Spacing(0.25, 1.5), 0.0, "ff_paper", None)
    assert _load(uavs={"count": 1}).uavs.count == 1 and _load().uavs == t.Uavs()


@pytest.mark.parametrize(
    ("uavs", "message"),
    [
        ({"count": 0}, "uavs.count: must be >= 1, got 0"),
        ({"count": 256}, "uavs.count: must be <= 255 (uint8 ids), got 256"),
        ({"takeoff_interval_s": -1}, "uavs.takeoff_interval_s: must be >= 0, got -1"),
        ({"vehicle_model": "x"}, "uavs.vehicle_model: must be one of"),
    ],
)
def test_a_bad_fleet_is_named(uavs, message):
    if message.endswith("one of"):
        with pytest.raises(ScenarioError, match=r"^<dict>: uavs\.vehicle_model: must be one of \["):
            _load(uavs=uavs)
    else:
        _refused(message, uavs=uavs)


def test_the_area_must_have_a_positive_width_and_height():
    assert _load().area == t.Area(-10.0, 100.0, 5.0, 400.0)
    _refused("area.x_max_m: must be > x_min_m (-10), got -10", **{"area": {**AREA, "x_max_m": -10}})
    _refused("area.y_max_m: must be > y_min_m (5), got 5", **{"area": {**AREA, "y_max_m": 5}})


def test_the_physics_period_must_divide_the_control_period():
    assert _load(
        timing={"control_period_s": 0.1, "physics_period_s": 0.01, "max_duration_s": 60}
    ).timing == t.Timing(0.1, 0.01, 60.0)
    assert _load(timing={"control_period_s": 0.1, "physics_period_s": 0.1}).timing.substeps == 1
    _refused(
        "timing.physics_period_s: must divide control_period_s (0.1), got 0.03",
        timing={"control_period_s": 0.1, "physics_period_s": 0.03},
    )
    _refused(
        "timing.physics_period_s: must divide control_period_s (0.1), got 0.2",
        timing={"control_period_s": 0.1, "physics_period_s": 0.2},
    )
    _refused("timing.max_duration_s: must be > 0, got 0", timing={"max_duration_s": 0})


def test_the_vehicle_bounds():
    v = _load(
        vehicle={"process_noise_sigma": 0, "collision_radius_m": 0, "v_stall_mps": 10, "v_max_mps": 10.5}
    ).vehicle
    assert (v.process_noise_sigma, v.collision_radius_m, v.v_stall_mps, v.v_max_mps) == (0.0, 0.0, 10.0, 10.5)
    _refused(
        "vehicle.v_max_mps: must be > v_stall_mps (10), got 10", vehicle={"v_stall_mps": 10, "v_max_mps": 10}
    )
    _refused("vehicle.refill_height_m: must be > 0, got 0", vehicle={"refill_height_m": 0})
    _refused("vehicle.process_noise_sigma: must be >= 0, got -1", vehicle={"process_noise_sigma": -1})


# --- terrain, lakes, sensors ----------------------------------------------------------------------
def test_the_terrain_and_its_hills():
    terr = _load(
        terrain={
            "base_m": 2.0,
            "slope_x": 0.1,
            "slope_y": -0.2,
            "hills": [{"x_m": 5, "y_m": 6, "height_m": 7, "sigma_m": 8}],
        }
    ).terrain
    assert (terr.base_m, terr.slope_x, terr.slope_y) == (2.0, 0.1, -0.2)
    assert terr.hills == (Hill(x_m=5.0, y_m=6.0, height_m=7.0, sigma_m=8.0),)
    flat = _load().terrain
    assert (flat.base_m, flat.slope_x, flat.slope_y, tuple(flat.hills)) == (0.0, 0.0, 0.0, ())
    _refused(
        "terrain.hills[0].sigma_m: must be > 0, got 0",
        terrain={"hills": [{"x_m": 5, "y_m": 6, "height_m": 7, "sigma_m": 0}]},
    )


def test_lakes_are_discs_in_order():
    lakes = _load(
        lakes=[{"x_m": 1, "y_m": 12, "diameter_m": 3}, {"x_m": -4, "y_m": 15, "diameter_m": 60}]
    ).lakes
    assert lakes == (Lake(1.0, 12.0, 3.0), Lake(-4.0, 15.0, 60.0))
    assert _load().lakes == ()
    _refused("lakes: must be a list, got dict", lakes={"x_m": 1})
    _refused(
        "lakes[1].diameter_m: must be > 0, got 0",
        lakes=[{"x_m": 1, "y_m": 2, "diameter_m": 3}, {"x_m": 1, "y_m": 2, "diameter_m": 0}],
    )


def test_sensor_fields_are_probabilities_noises_or_rates():
    s = _load(
        sensors={
            "gps": {"rate_hz": 5, "sigma_m": 0, "p_valid": 0},
            "altimeter": {"rate_hz": 20, "sigma_m": 0.5, "p_valid": 1, "max_range_m": 55},
            "gyro": {"rate_hz": 50, "sigma_radps": 0, "p_valid": 0.5},
            "fire": {
                "rate_hz": 2,
                "range_m": 30,
                "position_sigma_m": 0,
                "extent_sigma_m": 0,
                "p_valid": 0.25,
            },
        }
    ).sensors
    assert s == t.Sensors(
        t.GpsSpec(5.0, 0.0, 0.0),
        t.AltimeterSpec(20.0, 0.5, 1.0, 55.0),
        t.GyroSpec(50.0, 0.0, 0.5),
        t.FireSensorSpec(2.0, 30.0, 0.0, 0.0, 0.25),
    )
    assert _load().sensors == t.Sensors()
    _refused("sensors.gps.p_valid: must be <= 1, got 1.5", sensors={"gps": {"p_valid": 1.5}})
    _refused("sensors.gyro.p_valid: must be >= 0, got -0.5", sensors={"gyro": {"p_valid": -0.5}})
    _refused("sensors.altimeter.max_range_m: must be > 0, got 0", sensors={"altimeter": {"max_range_m": 0}})
    _refused("sensors.fire.rate_hz: must be > 0, got 0", sensors={"fire": {"rate_hz": 0}})
    _refused("sensors.fire.extent_sigma_m: must be >= 0, got -1", sensors={"fire": {"extent_sigma_m": -1}})
    _refused("sensors.gyro.sigma_radps: must be >= 0, got -1", sensors={"gyro": {"sigma_radps": -1}})


@pytest.mark.parametrize(
    ("terrain", "message"),
    [
        ({"hills": 3}, "terrain.hills: must be a list, got int"),
        ({"base_m": "x"}, "terrain.base_m: must be a number, got 'x'"),
        ({"slope_x": "x"}, "terrain.slope_x: must be a number, got 'x'"),
        ({"slope_y": "x"}, "terrain.slope_y: must be a number, got 'x'"),
    ],
)
def test_a_bad_terrain_field_is_named(terrain, message):
    _refused(message, terrain=terrain)


def test_the_period_ratio_edges():
    # a physics period above the control period, even by a whole factor, is no divisor
    _refused(
        "timing.physics_period_s: must divide control_period_s (0.1), got 1e+06",
        timing={"control_period_s": 0.1, "physics_period_s": 1e6},
    )
    _refused("timing.physics_period_s: must be > 0, got 0", timing={"physics_period_s": 0})
    # the ratio's float tolerance: a control period 1e-9 short of the physics period is one substep
    assert _load(timing={"control_period_s": 1 - 1e-9, "physics_period_s": 1.0}).timing.substeps == 1


@pytest.mark.parametrize(
    ("uavs", "message"),
    [
        (3, "uavs: must be a mapping, got int"),
        ({"nope": 1}, "uavs.nope: unknown field; expected one of"),
        ({"spacing": {"dx_m": "x"}}, "uavs.spacing.dx_m: must be a number, got 'x'"),
        (
            {"vehicle_model": "coordinated_turn", "airframe": "nope"},
            "uavs.airframe: unknown airframe 'nope'; presets: ",
        ),
    ],
)
def test_a_bad_fleet_section_is_named_with_its_path(uavs, message):
    with pytest.raises(ScenarioError, match="^" + re.escape(f"<dict>: {message}")):
        _load(uavs=uavs)


def test_a_fixed_wing_fleet_keeps_its_model_and_airframe():
    from fire_uav_common.scenario import AIRFRAMES

    u = _load(uavs={"vehicle_model": "coordinated_turn"}).uavs
    assert u.vehicle_model == "coordinated_turn" and u.airframe == AIRFRAMES["small_uav"]


@pytest.mark.parametrize(
    ("comms", "message"),
    [
        (3, "comms: must be a mapping, got int"),
        ({"nope": 1}, "comms.nope: unknown field; expected one of ['loss_probability', 'outages']"),
        ({"outages": 3}, "comms.outages: must be a list, got int"),
        ({"outages": [3]}, "comms.outages[0]: must be a mapping, got int"),
        (
            {"outages": [{"from": 0, "to": 1, "start_s": 0, "end_s": 1, "x": 2}]},
            "comms.outages[0].x: unknown field; expected one of ['end_s', 'from', 'start_s', 'to']",
        ),
        # the missing keys are named in sorted order, not in the order they are read
        ({"outages": [{"to": 1, "start_s": 0}]}, "comms.outages[0].end_s: required field missing"),
        (
            {"outages": [{"from": 0, "to": 1, "start_s": 0, "end_s": "x"}]},
            "comms.outages[0].end_s: must be a number, got 'x'",
        ),
    ],
)
def test_a_bad_comms_section_is_named_with_its_path(comms, message):
    _refused(message, uavs={"count": 3}, comms=comms)
