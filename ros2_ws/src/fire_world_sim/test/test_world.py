"""World: determinism, protocol step semantics, mission completion; rclpy-free modules."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest
from fire_world_sim.vehicle import Status
from fire_world_sim.world import Action, Command, EventType, World

from .conftest import SCENARIOS, make_scenario


def fly(world: World, steps: int) -> list:
    out = []
    for k in range(steps):
        cmds = {i: Command(50.0, 3.0 if k < 50 else 0.0, 0.3) for i in range(world.uav_count)}
        out.append(world.step(cmds))
    return out


def test_same_seed_same_truth(tiny) -> None:
    a = fly(World(tiny, seed=4), 100)
    b = fly(World(tiny, seed=4), 100)
    c = fly(World(tiny, seed=5), 100)
    assert [r.vehicles for r in a] == [r.vehicles for r in b]
    assert [r.bundles[0].gps for r in a] == [r.bundles[0].gps for r in b]
    assert a[-1].vehicles != c[-1].vehicles


def test_bundle_contents_and_stamps(tiny) -> None:
    w = World(tiny, seed=0)
    r = fly(w, 11)[-1]
    assert r.step == 10 and r.stamp_ns == 1_100_000_000
    b = r.bundles[1]
    assert b.step == 10 and b.stamp_ns == r.stamp_ns and b.control_period_s == pytest.approx(0.1)
    assert len(b.gyro) <= 10 and len(b.altimeter) <= 3 and len(b.gps) <= 1
    assert all(1_000_000_000 < g.stamp_ns <= 1_100_000_000 for g in b.gyro)
    assert b.vehicle_status == Status.AIRBORNE and b.water_kg == 2000.0


def test_drop_applied_with_the_commands_of_the_step() -> None:
    sc = make_scenario(
        lakes=[],
        uavs={"count": 1, "first": {"x_m": 100.0, "y_m": 100.0, "yaw_rad": 0.0}},
        vehicle={"process_noise_sigma": 0.0},
        fires={"analytic": [{"x_m": 105.0, "y_m": 100.0, "sigma_m": 20.0}]},
    )
    w = World(sc, seed=0)
    w.step({0: Command(50.0, 10.0, 0.0)})
    r = w.step({0: Command(50.0, 0.0, 0.0)}, {0: [Action.DROP]})
    drops = [e for e in r.events if e.type == EventType.DROP]
    assert len(drops) == 1 and drops[0].fire_id == 0 and drops[0].value == 2000.0
    assert r.fires[0].extent_m == pytest.approx(10.0) and r.vehicles[0].water_kg == 0.0


def test_silent_agent_crashes_and_gets_no_more_bundles(tiny) -> None:
    w = World(tiny, seed=0)
    w.step({0: Command(50.0, 5.0, 0.0), 1: Command(50.0, 5.0, 0.0)})
    crash = None
    for _ in range(40):
        r = w.step({0: Command(50.0, 0.0, 0.1)})
        if any(e.type == EventType.CRASH for e in r.events):
            crash = r
            break
    assert crash is not None and crash.step == 30  # 3.0 s / 0.1 s of misses
    assert 1 not in crash.bundles and 0 in crash.bundles
    assert w.awaited_uavs() == [0]


def test_mission_complete_when_fires_out_and_landed() -> None:
    sc = make_scenario(
        uavs={"count": 1, "first": {"x_m": 100.0, "y_m": 100.0, "yaw_rad": 0.0}},
        vehicle={"process_noise_sigma": 0.0},
        fires={"analytic": [{"x_m": 105.0, "y_m": 100.0, "sigma_m": 3.0}]},
    )
    w = World(sc, seed=0)
    w.step({0: Command(50.0, 0.5, 0.0)})
    r = w.step({0: Command(50.0, -0.5, 0.0)}, {0: [Action.DROP]})
    assert r.fires[0].status == 1 and not r.complete
    assert any(e.type == EventType.EXTINGUISHED for e in r.events)
    r = w.step({0: Command(0.0, 0.0, 0.0)})
    assert r.vehicles[0].status == Status.LANDED and r.complete
    assert [e.type for e in r.events][-1] == EventType.MISSION_COMPLETE


def test_max_duration(tiny) -> None:
    w = World(
        make_scenario(
            timing={"max_duration_s": 1.0}, fires={"analytic": [{"x_m": 1, "y_m": 1, "sigma_m": 5}]}
        )
    )
    results = [w.step({}) for _ in range(10)]
    assert results[-1].complete and "max_duration_s" in results[-1].complete_reason
    assert not results[-2].complete


@pytest.mark.parametrize("name", ["grass_wind", "grass_to_brush", "wind_shift"])
def test_raster_scenarios_step(name: str) -> None:
    from fire_uav_common.scenario import load_scenario

    w = World(load_scenario(SCENARIOS / f"{name}.yaml"), seed=0)
    for _ in range(20):
        r = w.step({})
    assert r.fires and r.fires[0].area_m2 > 0


def test_algorithm_modules_do_not_import_rclpy() -> None:
    pkg = Path(__file__).resolve().parents[1] / "fire_world_sim"
    for path in pkg.rglob("*.py"):
        if path.name in ("world_node.py",) or path.name.startswith(("record", "replay", "bag")):
            continue
        tree = ast.parse(path.read_text())
        names = [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
        names += [n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
        assert not any(n.split(".")[0] == "rclpy" for n in names), path


def _two_vehicles(dy_m: float, radius_m: float = 3.0) -> World:
    """UAV 0 at (100, 500) heading east and UAV 1 at (900, 500 + dy) heading west, same altitude."""
    sc = make_scenario(
        lakes=[],
        uavs={
            "count": 2,
            "first": {"x_m": 100.0, "y_m": 500.0, "yaw_rad": 0.0},
            "spacing": {"dx_m": 0, "dy_m": 0},
        },
        vehicle={"process_noise_sigma": 0.0, "collision_radius_m": radius_m},
        fires={"analytic": [{"x_m": 10.0, "y_m": 10.0, "sigma_m": 5.0}]},
    )
    w = World(sc, seed=0)
    w.vehicles[1].x_m, w.vehicles[1].y_m, w.vehicles[1].yaw_rad = 900.0, 500.0 + dy_m, math.pi
    return w


def _fly_level(w: World, steps: int) -> list:
    out = [w.step({0: Command(50.0, 10.0, 0.0), 1: Command(50.0, 10.0, 0.0)})]  # take off together
    for _ in range(steps):
        out.append(w.step({0: Command(50.0, 0.0, 0.0), 1: Command(50.0, 0.0, 0.0)}))
    return out


def test_head_on_collision_crashes_both() -> None:
    w = _two_vehicles(dy_m=0.0)
    res = _fly_level(w, 100)  # closing at 100 m/s from 800 m: they meet after ~8 s
    crashes = [e for r in res for e in r.events if e.type == EventType.CRASH]
    assert sorted(e.uav_id for e in crashes) == [0, 1]
    assert "collision with uav 1" in next(e.detail for e in crashes if e.uav_id == 0)
    assert res[-1].collisions == 1 and res[-1].min_separation_m < 3.0
    # they met half way, x ~ 500 (both flew the same speed from 100 and 900)
    assert all(abs(e.x_m - 500.0) < 5.0 for e in crashes)
    assert all(v.status == Status.CRASHED for v in res[-1].vehicles)
    # the bundle of the collision step tells each agent its vehicle fell; then no more bundles
    k = next(i for i, r in enumerate(res) if any(e.type == EventType.CRASH for e in r.events))
    assert (
        res[k].bundles[0].vehicle_status == Status.CRASHED
        and res[k].bundles[1].vehicle_status == Status.CRASHED
    )
    assert res[k + 1].bundles == {}


def test_passing_pair_measures_closest_approach_without_crashing() -> None:
    w = _two_vehicles(dy_m=12.0)
    res = _fly_level(w, 100)
    assert not [e for r in res for e in r.events if e.type == EventType.CRASH]
    assert res[-1].collisions == 0
    # parallel opposite tracks 12 m apart: closest approach is 12 m, sampled at 100 Hz (1 m apart)
    assert res[-1].min_separation_m == pytest.approx(12.0, abs=0.1)
    # before they are both airborne there is no pair to measure
    assert _two_vehicles(dy_m=12.0).step({}).min_separation_m == math.inf


def test_collision_radius_zero_turns_collisions_off() -> None:
    w = _two_vehicles(dy_m=0.0, radius_m=0.0)
    res = _fly_level(w, 100)
    assert res[-1].collisions == 0 and res[-1].min_separation_m < 1.0
    assert all(v.status == Status.AIRBORNE for v in res[-1].vehicles)


def test_outages_must_name_uavs_of_the_fleet_flown() -> None:
    """uav_count smaller than the scenario's fleet: an outage naming a missing UAV is refused."""
    from fire_uav_common.scenario import ScenarioError

    s = make_scenario(uavs={"count": 3}, comms={"outages": [{"from": 2, "to": 0, "start_s": 1, "end_s": 2}]})
    assert World(s, uav_count=3).uav_count == 3
    with pytest.raises(
        ScenarioError, match=r"comms\.outages\[0\]\.from: UAV 2 does not exist: the fleet has ids 0\.\.1"
    ):
        World(s, uav_count=2)
