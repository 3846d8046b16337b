"""World: determinism, protocol step semantics, mission completion; rclpy-free modules."""

from __future__ import annotations

import ast
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
