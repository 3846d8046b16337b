"""What an agent knows a priori (fire_uav_agent.agent_config), against the scenario it came from.

Truth: the scenario's own fields, read here one by one (docs/scenario.md names each), and the
documented bounds of each config field (its module and field docs). Fast on purpose (the
mutation selection of ``fire_uav_agent.agent_config`` runs this file once per mutant): no
Agent is built, one shipped scenario is loaded once.
"""

from __future__ import annotations

import dataclasses
import math

import pytest
from fire_uav_agent.agent_config import (
    DEFAULT_DROP_RADIUS_M,
    AgentConfig,
    GuidanceConfig,
    config_from_scenario,
)
from fire_uav_agent.coverage import VehicleLimits
from fire_uav_agent.errors import ConfigError
from fire_uav_agent.separation import SeparationConfig
from fire_uav_agent.testing.harness import scenario_path
from fire_uav_common import scenario as sc
from fire_uav_common.scenario import LinkOutage, load_scenario
from fire_uav_common.terrain import Lake


@pytest.fixture(scope="module")
def base() -> sc.Scenario:
    return load_scenario(scenario_path("ff_two_fires"))


def _odd(base: sc.Scenario, **fires) -> sc.Scenario:
    """ff_two_fires with every field the mapping reads set to a value no default has (ids, poses
    and times differing per axis, so a swapped or dropped field shows)."""
    return dataclasses.replace(
        base,
        seed=7,
        area=sc.Area(10.0, 610.0, -20.0, 580.0),
        lakes=(Lake(40.0, 60.0, 90.0), Lake(500.0, 520.0, 80.0)),
        timing=sc.Timing(0.2, 0.02, 333.0),
        uavs=dataclasses.replace(
            base.uavs,
            count=4,
            first=sc.Pose(12.5, 34.5, 1.5, 0.3),
            spacing=sc.Spacing(4.0, 30.0),
            takeoff_interval_s=3.5,
        ),
        comms=sc.Comms(0.125, (LinkOutage(2, 1, 5.0, 6.5), LinkOutage(0, 3, 1.0, 9.0))),
        mission=dataclasses.replace(base.mission, crash_threshold_steps=7, monitors_per_fire=2),
        fires=dataclasses.replace(base.fires, **({"drop_radius_m": 17.0} | fires)),
    )


def test_every_field_is_the_scenarios(base):
    s = _odd(base)
    c = config_from_scenario(s, 2)
    assert (c.uav_id, c.uav_count, c.seed) == (2, 4, 7)
    assert c.area_m == (10.0, 610.0, -20.0, 580.0)
    assert c.terrain is s.terrain and c.lakes == s.lakes and isinstance(c.lakes, tuple)
    # UAV 2 of the line from (12.5, 34.5) every (4, 30) m (scenario uavs.first / spacing)
    assert c.start_pose == (12.5 + 2 * 4.0, 34.5 + 2 * 30.0, 1.5, 0.3)
    assert all(type(v) is float for v in c.start_pose)
    assert c.takeoff_interval_s == 3.5
    assert c.timing is s.timing and c.vehicle is s.vehicle and c.sensors is s.sensors
    assert c.mission == s.mission and c.airframe is None
    assert c.loss_probability == 0.125
    assert c.outages == (LinkOutage(2, 1, 5.0, 6.5), LinkOutage(0, 3, 1.0, 9.0))
    assert c.drop_radius_m == 17.0 and c.pattern_drops is False
    # the views of the sub-configs
    assert (c.control_period_s, c.physics_period_s) == (0.2, 0.02)
    assert (c.crash_threshold_steps, c.monitors_per_fire) == (7, 2)
    assert c.limits == VehicleLimits.of(s.vehicle)
    assert c.fire_range_m == s.sensors.fire.range_m
    assert c.fires_known is False and c.search_first is False


def test_the_scenario_values_are_converted_to_their_field_types(base):
    # a scenario built in code may hold ints where the config holds floats (the start pose, the
    # area, the takeoff interval, the loss) and a list of lakes: the config holds floats and tuples
    s = dataclasses.replace(
        _odd(base),
        area=sc.Area(10, 610, -20, 580),
        lakes=[Lake(40.0, 60.0, 90.0)],
        uavs=dataclasses.replace(
            base.uavs, count=3, first=sc.Pose(12, 34, 1, 0), spacing=sc.Spacing(4, 30), takeoff_interval_s=3
        ),
        comms=sc.Comms(0, (LinkOutage(2, 1, 5, 6),)),
    )
    c = config_from_scenario(s, 1, loss_probability=None)
    for v in (*c.area_m, *c.start_pose, c.takeoff_interval_s, c.loss_probability, c.drop_radius_m):
        assert type(v) is float, (v, c)
    for o in c.outages:
        assert type(o.start_s) is float and type(o.end_s) is float
    assert c.lakes == (Lake(40.0, 60.0, 90.0),) and isinstance(c.lakes, tuple)


def test_the_runners_arguments_override_the_scenario(base):
    s = _odd(base)
    out = (LinkOutage(3, 0, 2.0, 4.0),)
    c = config_from_scenario(
        s,
        5,
        uav_count=6,
        seed=11,
        loss_probability=0.0,
        outages=out,
        crash_threshold_steps=3,
        monitors_per_fire=0,
    )
    assert (c.uav_id, c.uav_count, c.seed, c.loss_probability) == (5, 6, 11, 0.0)
    assert c.outages == out and isinstance(c.outages, tuple)
    assert (c.crash_threshold_steps, c.monitors_per_fire) == (3, 0)
    assert c.mission == dataclasses.replace(s.mission, crash_threshold_steps=3, monitors_per_fire=0)
    # the sixth UAV's start is the line's sixth pose, beyond uavs.count
    assert c.start_pose == (12.5 + 5 * 4.0, 34.5 + 5 * 30.0, 1.5, 0.3)
    # an empty outage list given by the runner replaces the scenario's (not "no override")
    assert config_from_scenario(s, 0, outages=()).outages == ()
    # one override alone leaves the other mission field the scenario's
    c1 = config_from_scenario(s, 0, crash_threshold_steps=4)
    assert (c1.crash_threshold_steps, c1.monitors_per_fire) == (4, 2)
    c2 = config_from_scenario(s, 0, monitors_per_fire=1)
    assert (c2.crash_threshold_steps, c2.monitors_per_fire) == (7, 1)


def test_agent_options_are_further_fields(base):
    c = config_from_scenario(_odd(base), 0, monitor_alpha=2.5, avoidance=False)
    assert (c.monitor_alpha, c.avoidance) == (2.5, False)
    own = SeparationConfig(vertical_rates=False, vertical_m=7.0)
    assert config_from_scenario(_odd(base), 0, separation=own).separation is own


def test_the_drop_footprint_and_model(base):
    assert (
        config_from_scenario(_odd(base, drop_radius_m=None), 0).drop_radius_m == DEFAULT_DROP_RADIUS_M == 20.0
    )
    three = config_from_scenario(_odd(base, drop_radius_m=3), 0).drop_radius_m
    assert three == 3.0 and type(three) is float
    assert config_from_scenario(_odd(base, drop_model="pattern"), 0).pattern_drops is True
    assert config_from_scenario(_odd(base, drop_model="disc"), 0).pattern_drops is False


def test_a_pattern_drop_fleet_knows_the_raster_fuel_maps_coverage_levels(base):
    """Pattern drops over a raster fire: the agent gets the fuel map's coverage levels (drop
    guides' Table 1 as drop_coverage cites it: Anderson 1 short grass 1, Anderson 4 chaparral
    6 gal/100 ft^2), a patch's model inside it; a disc drop or no raster fire: no levels."""
    raster = sc.Raster(fuel_model=1, fuel_patches=(sc.FuelPatch(100.0, 200.0, 300.0, 400.0, 4),))
    c = config_from_scenario(_odd(base, drop_model="pattern", raster=raster), 0)
    assert c.coverage_levels is not None
    assert c.coverage_levels.at(50.0, 50.0) == 1.0
    assert c.coverage_levels.at(150.0, 350.0) == 6.0
    assert config_from_scenario(_odd(base, drop_model="disc", raster=raster), 0).coverage_levels is None
    assert config_from_scenario(_odd(base, drop_model="pattern", raster=None), 0).coverage_levels is None


def test_a_fixed_wing_fleet_hands_its_airframe_to_the_agent(base):
    # uavs.vehicle_model coordinated_turn: the scenario's airframe envelope (small_uav by default)
    s = load_scenario(scenario_path("ff_two_fires"), overrides={"uavs.vehicle_model": "coordinated_turn"})
    assert s.uavs.airframe is not None
    assert config_from_scenario(s, 0).airframe is s.uavs.airframe


@pytest.mark.parametrize(
    ("model", "resolves"),
    [
        ("coordinated_turn", True),  # measured there (test_separation_vertical_resolution.py)
        ("jsbsim", False),  # the J3Cub's ff_two_fires seed 2 came to 6.4 m with it (13.9 m without)
        ("ff_paper", False),  # FF's unicycle turns at 10 rad/s: the heading alone
    ],
)
def test_the_vertical_resolution_is_on_for_coordinated_turn_only(model, resolves):
    """The avoider's vertical sense (docs/suppression.md, "Vertical resolution on fixed-wings"):
    exactly True on the kinematic fixed-wing, False elsewhere."""
    sc_ = load_scenario(scenario_path("grass_brush_hill"), overrides={"uavs.vehicle_model": model})
    assert config_from_scenario(sc_, 0, uav_count=5, seed=3).separation.vertical_resolution is resolves


def test_known_fires_and_search_first_come_from_the_mission(base):
    s = dataclasses.replace(
        base, mission=dataclasses.replace(base.mission, prior_fires="known", search_first=True)
    )
    c = config_from_scenario(s, 0)
    assert c.fires_known is True and c.search_first is True


@pytest.mark.parametrize("uid", [-1, 4, 9])
def test_a_uav_id_outside_the_fleet_is_named_before_any_pose_is_read(base, uid):
    with pytest.raises(
        ConfigError, match=rf"^uav_id must be in 0..uav_count-1, got uav_id={uid}, uav_count=4$"
    ):
        config_from_scenario(_odd(base), uid)


def test_the_last_uav_of_the_fleet_is_valid(base):
    assert config_from_scenario(_odd(base), 3).uav_id == 3
    assert config_from_scenario(_odd(base), 0, uav_count=1).uav_count == 1


# --- AgentConfig's own checks ----------------------------------------------------------------------
@pytest.mark.parametrize(("uid", "n"), [(-1, 2), (2, 2), (0, 0)])
def test_agent_config_refuses_an_id_outside_the_fleet(uid, n):
    with pytest.raises(
        ConfigError, match=rf"^uav_id must be in 0..uav_count-1, got uav_id={uid}, uav_count={n}$"
    ):
        AgentConfig(uav_id=uid, uav_count=n)


def test_agent_config_accepts_the_bounds():
    AgentConfig(uav_id=0, uav_count=1)
    AgentConfig(uav_id=1, uav_count=2, loss_probability=0.0)
    AgentConfig(uav_id=1, uav_count=2, loss_probability=1.0)
    AgentConfig(uav_id=0, uav_count=1, mission=sc.MissionSettings(crash_threshold_steps=1))
    AgentConfig(uav_id=0, uav_count=1, prior_fires=((1.0, -2.0, 1e-9),))


@pytest.mark.parametrize(
    "timing", [sc.Timing(0.0, 0.01), sc.Timing(0.1, 0.0), sc.Timing(-0.1, 0.01), sc.Timing(math.nan, 0.01)]
)
def test_agent_config_refuses_non_positive_periods(timing):
    with pytest.raises(ConfigError, match=r"^control_period_s and physics_period_s must be > 0$"):
        AgentConfig(uav_id=0, uav_count=1, timing=timing)


@pytest.mark.parametrize("steps", [0, -3])
def test_agent_config_refuses_a_crash_threshold_under_one_step(steps):
    with pytest.raises(ConfigError, match=rf"^crash_threshold_steps must be >= 1, got {steps}$"):
        AgentConfig(uav_id=0, uav_count=1, mission=sc.MissionSettings(crash_threshold_steps=steps))


@pytest.mark.parametrize("p", [-0.01, 1.01, math.nan])
def test_agent_config_refuses_a_loss_outside_0_1(p):
    with pytest.raises(ConfigError, match=rf"^loss_probability must be in \[0, 1\], got {p}$"):
        AgentConfig(uav_id=0, uav_count=1, loss_probability=p)


@pytest.mark.parametrize(
    "bad",
    [
        (1.0, 2.0),
        (1.0, 2.0, 3.0, 4.0),
        (math.nan, 0.0, 1.0),
        (0.0, math.inf, 1.0),
        (0.0, 0.0, 0.0),
        (0.0, 0.0, -1.0),
    ],
)
def test_agent_config_refuses_a_bad_prior_fire_naming_its_index(bad):
    with pytest.raises(
        ConfigError, match=r"^prior_fires\[1\] must be finite \(x_m, y_m, extent_m > 0\), got "
    ):
        AgentConfig(uav_id=0, uav_count=1, prior_fires=((1.0, 1.0, 1.0), bad))


# --- GuidanceConfig ------------------------------------------------------------------------------
def test_every_guidance_field_may_be_zero_except_the_flat_fraction():
    names = [f.name for f in dataclasses.fields(GuidanceConfig) if f.name != "land_flat_fraction"]
    assert GuidanceConfig(**dict.fromkeys(names, 0)).ff_layers == 0
    for f in (1e-9, 0.5, 1.0 - 1e-9):
        assert GuidanceConfig(land_flat_fraction=f).land_flat_fraction == f


@pytest.mark.parametrize("name", [f.name for f in dataclasses.fields(GuidanceConfig)])
@pytest.mark.parametrize("value", [-1e-9, math.nan])
def test_a_negative_or_nan_guidance_field_is_named(name, value):
    with pytest.raises(ConfigError, match=rf"^GuidanceConfig\.{name} must be >= 0, got {value}$"):
        GuidanceConfig(**{name: value})


@pytest.mark.parametrize("value", [0.0, 1.0, 2.0])
def test_the_flat_fraction_must_lie_strictly_inside_0_1(value):
    with pytest.raises(
        ConfigError, match=rf"^GuidanceConfig\.land_flat_fraction must be in \(0, 1\), got {value}$"
    ):
        GuidanceConfig(land_flat_fraction=value)
