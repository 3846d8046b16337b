"""World's step contract (docs/protocol.md "World, step k"; events: docs/protocol.md "Events"):
configuration errors, command and payload events with their stamps and values, refill events,
per-vehicle noise streams, bundles, and the fires the world advances (compared with the fire
model run on its own)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from fire_uav_common.scenario import Scenario
from fire_world_sim.errors import ConfigError
from fire_world_sim.fires import RasterFireModel
from fire_world_sim.vehicle import Status
from fire_world_sim.world import Action, Command, EventType, World

from .conftest import make_scenario

GO = Command(50.0, 5.0, 0.0)  # takeoff
LEVEL = Command(50.0, 0.0, 0.0)
FAR_FIRE = {"analytic": [{"x_m": 900.0, "y_m": 900.0, "sigma_m": 5.0}]}


def scenario(count=1, x=100.0, y=100.0, vehicle=None, fires=None, **kw) -> Scenario:
    return make_scenario(
        lakes=kw.pop("lakes", [{"x_m": 100.0, "y_m": 100.0, "diameter_m": 90.0}]),
        uavs={
            "count": count,
            "first": {"x_m": x, "y_m": y, "yaw_rad": 0.0},
            "spacing": {"dx_m": 0, "dy_m": 30},
        },
        vehicle={"process_noise_sigma": 0.0, **(vehicle or {})},
        fires=fires or FAR_FIRE,
        **kw,
    )


def events(results, kind) -> list:
    return [e for r in results for e in r.events if e.type == kind]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"uav_count": -1}, r"^uav_count must be in 0\.\.255, got -1$"),
        ({"uav_count": 256}, r"^uav_count must be in 0\.\.255, got 256$"),
        ({"uav_count": 1, "no_fleet": True}, r"^no_fleet needs uav_count 0, got 1$"),
        ({"seed": -1}, r"^seed must be >= 0, got -1$"),
    ],
)
def test_bad_arguments_are_refused_with_one_line(kwargs: dict, match: str) -> None:
    with pytest.raises(ConfigError, match=match):
        World(scenario(), **kwargs)


def test_largest_fleet_and_no_fleet_are_accepted() -> None:
    # 255 UAVs 3 m apart in a line all start inside the 1000 m area
    line = make_scenario(
        uavs={"count": 2, "first": {"x_m": 100.0, "y_m": 100.0}, "spacing": {"dx_m": 0, "dy_m": 3}},
        fires=FAR_FIRE,
    )
    assert World(line, uav_count=255).uav_count == 255
    w = World(scenario(count=3), no_fleet=True)
    assert w.uav_count == 0 and w.vehicles == [] and w.step({}).bundles == {}


def test_physics_period_must_divide_the_control_period() -> None:
    sc = scenario()
    bad = dataclasses.replace(sc, timing=dataclasses.replace(sc.timing, physics_period_s=0.03))
    with pytest.raises(
        ConfigError, match=r"^physics_period_s must divide control_period_s in whole nanoseconds$"
    ):
        World(bad)


def test_fewer_uavs_than_the_scenario_flies_only_those() -> None:
    w = World(scenario(count=3), uav_count=2)
    assert [v.uav_id for v in w.vehicles] == [0, 1]
    assert sorted(w.step({}).bundles) == [0, 1]


def test_each_vehicle_has_its_own_noise_stream() -> None:
    w = World(scenario(count=2, vehicle={"process_noise_sigma": 1.0}), seed=3)
    for _ in range(20):
        r = w.step({0: GO, 1: GO})
    a, b = r.vehicles
    assert a.yaw_rad != b.yaw_rad and a.z_m != b.z_m  # same commands, other draws


def test_step_zero_missing_command_skips_only_that_vehicle() -> None:
    w = World(scenario(count=2), seed=0)
    r = w.step({1: GO})
    assert [e.uav_id for e in events([r], EventType.TAKEOFF)] == [1]
    assert not events([r], EventType.COMMAND_MISSED)
    assert r.vehicles[1].status == Status.AIRBORNE and r.vehicles[0].status == Status.ON_GROUND


def test_command_events_carry_stamp_uav_and_counts() -> None:
    w = World(scenario(count=1), seed=0)
    res = [w.step({0: Command(150.0, 5.0, 0.0)})]  # takeoff, clamped at t = 0
    res += [w.step({0: Command(150.0, 0.0, 0.0)}) for _ in range(60)]  # clamped every step
    res += [w.step({}) for _ in range(25)]  # silent: misses 1..25
    (take,) = events(res, EventType.TAKEOFF)
    assert take.stamp_ns == 0 and take.uav_id == 0 and take.x_m == 100.0
    clamps = events(res, EventType.COMMAND_CLAMPED)
    assert [e.stamp_ns for e in clamps] == [0, 5_000_000_000]  # throttled to one per 5 s
    assert [e.value for e in clamps] == [1.0, 51.0] and {e.uav_id for e in clamps} == {0}
    missed = events(res, EventType.COMMAND_MISSED)
    assert [e.value for e in missed] == [1.0, 11.0, 21.0]
    assert missed[0].stamp_ns == 61 * 100_000_000 and missed[0].uav_id == 0
    assert all(not r.complete and r.complete_reason == "" for r in res)


def test_landing_event() -> None:
    w = World(scenario(count=1), seed=0)
    w.step({0: Command(50.0, 1.0, 0.0)})  # 0.1 m up
    r = w.step({0: Command(30.0, 0.0, 0.0)})
    (land,) = events([r], EventType.LANDED)
    assert land.uav_id == 0 and land.stamp_ns == 100_000_000 and r.vehicles[0].status == Status.LANDED


def test_a_crashed_vehicle_does_not_stop_the_others() -> None:
    w = World(scenario(count=2), seed=0)
    w.step({0: GO, 1: GO})
    w.vehicles[0].crash("test")
    x1 = w.vehicles[1].x_m
    r = w.step({1: LEVEL})
    assert r.vehicles[1].x_m == pytest.approx(x1 + 5.0)  # 50 m/s for 0.1 s
    assert sorted(r.bundles) == [1] and r.bundles[1].uav_id == 1
    assert w.live_uavs() == [1] and w.awaited_uavs() == [1]


def test_a_silent_landed_vehicle_is_live_but_not_awaited() -> None:
    w = World(scenario(count=2), seed=0)
    w.step({0: Command(50.0, 1.0, 0.0), 1: GO})
    w.step({0: Command(30.0, 0.0, 0.0), 1: LEVEL})
    for _ in range(31):
        w.step({1: LEVEL})
    assert w.live_uavs() == [0, 1] and w.awaited_uavs() == [1]


def test_bundles_are_keyed_by_uav_and_stamped_in_integer_ns() -> None:
    w = World(scenario(count=2), seed=0)
    w.step({0: GO, 1: GO})
    r = w.step({0: LEVEL, 1: LEVEL})
    for uid, b in r.bundles.items():
        assert b.uav_id == uid
        stamps = [g.stamp_ns for g in b.gyro]
        assert stamps and all(isinstance(s, int) for s in stamps)
        assert all(100_000_000 < s <= 200_000_000 for s in stamps) and stamps == sorted(set(stamps))


def test_payload_of_every_vehicle_is_applied_and_unknown_ids_ignored() -> None:
    w = World(scenario(count=2), seed=0)
    w.step({0: GO, 1: GO})
    r = w.step({0: LEVEL, 1: LEVEL}, {0: [Action.DROP], 1: [Action.DROP], 2: [Action.DROP]})
    drops = events([r], EventType.DROP)
    assert sorted(e.uav_id for e in drops) == [0, 1] and all(e.value == 2000.0 for e in drops)
    assert all(e.stamp_ns == 100_000_000 and e.detail.startswith("missed") for e in drops)


def _refill(water_kg: float, steps: int, climb_at: int | None = None, rate_kgps: float = 400.0, x=100.0):
    w = World(scenario(count=1, x=x, vehicle={"refill_rate_kgps": rate_kgps}), seed=0)
    w.step({0: GO})  # 0.5 m up over the lake centre, heading east at 50 m/s
    w.vehicles[0].water_kg = water_kg
    res = [w.step({0: LEVEL}, {0: [Action.REFILL]})]
    for k in range(steps):
        res.append(w.step({0: Command(50.0, 100.0 if climb_at is not None and k >= climb_at else 0.0, 0.0)}))
    return w, res


def test_refill_event_when_the_tank_is_full() -> None:
    w, res = _refill(1900.0, 5)  # 100 kg at 400 kg/s: 0.25 s after the request at t = 0.1 s
    (ev,) = events(res, EventType.REFILL)
    assert ev.detail == "tank full" and ev.value == pytest.approx(100.0) and ev.uav_id == 0
    assert ev.stamp_ns == 350_000_000 and ev.fire_id == -1
    assert ev.x_m == pytest.approx(100.0 + 50.0 * 0.35) and ev.y_m == pytest.approx(100.0)
    assert res[-1].vehicles[0].water_kg == 2000.0


def test_refill_event_of_less_than_a_kilogram() -> None:
    _, res = _refill(1999.5, 2)
    (ev,) = events(res, EventType.REFILL)
    assert ev.value == pytest.approx(0.5) and ev.detail == "tank full"


def test_refill_event_when_leaving_the_lake_part_filled() -> None:
    # climbing at 100 m/s from step 2 on: above 15 m within 0.15 s, 4 kg per 10 ms substep before
    _, res = _refill(0.0, 6, climb_at=1)
    (ev,) = events(res, EventType.REFILL)
    assert ev.detail == "left the lake part-filled" and 0.0 < ev.value < 2000.0
    assert ev.value == pytest.approx(res[-1].vehicles[0].water_kg)
    # slow pump (0.04 kg per substep) near the lake's east shore: out after 20 substeps, 0.2 kg
    # short of full is still part-filled
    _, res = _refill(1999.0, 4, rate_kgps=4.0, x=130.0)
    (ev,) = events(res, EventType.REFILL)
    assert ev.detail == "left the lake part-filled" and ev.value == pytest.approx(0.8)


def _raster_scenario(lake_on_fire: bool = False) -> Scenario:
    lakes = [{"x_m": 62.5, "y_m": 62.5, "diameter_m": 60.0}] if lake_on_fire else []
    raster = {
        "cell_size_m": 5.0,
        "nx": 25,
        "ny": 25,
        "origin": {"x_m": 0.0, "y_m": 0.0},
        "fuel_model": 1,
        "wind": [{"start_s": 0.0, "speed_mps": 2.0, "direction_deg": 30.0}],
        "ignitions": [{"x_m": 62.5, "y_m": 62.5, "start_s": 0.0}],
        "spread_factor": 3.0,
    }
    return scenario(count=1, x=900.0, y=900.0, lakes=lakes, fires={"model": "raster", "raster": raster})


def test_world_advances_the_raster_fire_like_the_model_alone() -> None:
    sc = _raster_scenario()
    w = World(sc, seed=0)
    alone = RasterFireModel(sc.fires.raster, sc.terrain, lakes=sc.lakes, drop_radius_m=sc.fires.drop_radius_m)
    for k in range(40):
        r = w.step({})
        alone.step(k * 0.1, 0.1)
    assert r.fires[0].area_m2 == alone.truth()[0].area_m2 > 0
    assert np.array_equal(w.fires.state_grid(), alone.state_grid())
    (ign,) = events([World(sc, seed=0).step({})], EventType.IGNITION)
    assert ign.fire_id == 0 and ign.stamp_ns == 100_000_000 and ign.detail == "ignition"


def test_a_lake_under_the_ignition_keeps_the_world_fire_out() -> None:
    """The loader rejects such a scenario; a world given one anyway (built in code) keeps its
    lake cells unburnable."""
    from fire_uav_common.scenario import ScenarioError
    from fire_uav_common.terrain import Lake

    with pytest.raises(ScenarioError, match=r"fires\.raster\.ignitions\[0\]: .* is in lakes\[0\]"):
        _raster_scenario(lake_on_fire=True)
    sc = dataclasses.replace(_raster_scenario(), lakes=(Lake(62.5, 62.5, 60.0),))
    w = World(sc, seed=0)
    for _ in range(20):
        r = w.step({})
    assert r.fires[0].area_m2 == 0.0


def test_stamps_are_whole_periods_for_a_one_second_control_period() -> None:
    sc = scenario(timing={"control_period_s": 1.0, "physics_period_s": 0.05, "max_duration_s": 10.0})
    w = World(sc, seed=0)
    r = w.step({0: GO})
    assert r.stamp_ns == 1_000_000_000 and w.stamp_ns(4) == 5_000_000_000 and w.t_ns == 1_000_000_000


def test_vehicle_events_in_full() -> None:
    """docs/protocol.md "Events": vehicle events carry fire_id -1, the vehicle's position, their
    value (counts / kg / 0) and their detail text."""
    from fire_world_sim.world import MissionEventRecord as Event

    w = World(scenario(count=1, x=300.0, y=300.0, lakes=[]), seed=0)
    r0 = w.step({0: Command(150.0, 1.0, 0.0)})  # takeoff, clamped
    assert r0.events == [
        Event(EventType.TAKEOFF, 0, 0, -1, 300.0, 300.0, 0.0, "takeoff"),
        Event(EventType.COMMAND_CLAMPED, 0, 0, -1, 300.0, 300.0, 1.0, "command outside the vehicle limits"),
    ]
    v = w.vehicles[0]
    x, y = v.x_m, v.y_m
    r1 = w.step({})
    assert r1.events == [
        Event(EventType.COMMAND_MISSED, 100_000_000, 0, -1, x, y, 1.0, "no valid command for this step")
    ]
    x, y = v.x_m, v.y_m
    r2 = w.step({0: Command(30.0, 0.0, 0.0)}, {0: [Action.DROP]})  # 0.2 m up, slow: lands
    assert r2.events == [
        Event(EventType.DROP, 200_000_000, 0, -1, x, y, 2000.0, "missed"),
        Event(EventType.LANDED, 200_000_000, 0, -1, x, y, 0.0, "landed"),
    ]
    w2 = World(scenario(count=1, x=300.0, y=300.0, lakes=[]), seed=0)
    w2.step({0: GO})
    w2.vehicles[0].water_kg = 0.0
    x, y = w2.vehicles[0].x_m, w2.vehicles[0].y_m
    r = w2.step({0: LEVEL}, {0: [Action.DROP]})
    assert r.events == [Event(EventType.DROP, 100_000_000, 0, -1, x, y, 0.0, "tank empty")]
    res = [w2.step({}) for _ in range(30)]
    (crash,) = events(res, EventType.CRASH)
    v2 = w2.vehicles[0]
    assert crash == Event(EventType.CRASH, 3_100_000_000, 0, -1, v2.x_m, v2.y_m, 0.0, v2.crash_reason)
    assert res[-1].vehicles[0].commands_missed == 30 and res[-1].vehicles[0].water_kg == 0.0
