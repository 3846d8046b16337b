"""``--uavs 0`` means no fleet in every runner: the in-process runner burns the fire alone.

The truth it is measured against is the world's own no-fleet run (``World(no_fleet=True)``,
what ``scripts/run_mission SCENARIO --uavs 0`` starts as the world node): the same burned area
step for step. The slow test compares it with the process runner over DDS.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from fire_mission.inprocess import main, run_inprocess

ROOT = Path(__file__).resolve().parents[1]
SHORT = {"timing.max_duration_s": 8.0}  # 80 steps of the raster fire


def _world_alone(scenario: str, seed: int | None, overrides: dict) -> float:
    from fire_uav_agent.testing.harness import scenario_path
    from fire_uav_common.scenario import load_scenario
    from fire_world_sim.world import World

    w = World(load_scenario(scenario_path(scenario), overrides=overrides), seed, no_fleet=True)
    area = 0.0
    while not w.complete:
        r = w.step({})
        area = sum(float(f.area_m2) for f in r.fires)
    return area


@pytest.mark.parametrize(
    "scenario",
    [
        "monitor_grass",  # a raster fire that grows from its ignition: cheap to set up
        pytest.param("grass_running", marks=pytest.mark.slow),  # pre-burnt: ~3 s to set up each time
    ],
)
def test_zero_uavs_burns_the_fire_alone(scenario: str) -> None:
    d = run_inprocess(scenario, uavs=0, seed=1, overrides=SHORT)
    assert d["uav_count"] == 0
    assert d["drops_total"] == 0 and d["landed"] == [] and d["packets_received"] == 0
    assert d["burned_area_m2"] == pytest.approx(_world_alone(scenario, 1, SHORT), abs=0.0)
    assert d["burned_area_m2"] > 0
    assert d["mission_time_s"] == pytest.approx(8.0)


def test_no_uavs_argument_flies_the_scenarios_fleet() -> None:
    d = run_inprocess("tiny_test", seed=1, max_steps=5)
    from fire_uav_agent.testing.harness import scenario_path
    from fire_uav_common.scenario import load_scenario

    assert d["uav_count"] == load_scenario(scenario_path("tiny_test")).uavs.count > 0


def test_command_line_zero_uavs(tmp_path: Path) -> None:
    out = tmp_path / "s.json"
    code = main(
        [
            "monitor_grass",
            "--uavs",
            "0",
            "--seed",
            "1",
            "--set",
            "timing.max_duration_s=20",
            "--json",
            str(out),
        ]
    )
    assert code == 0
    d = json.loads(out.read_text())
    assert d["uav_count"] == 0 and d["drops_total"] == 0


def test_command_line_negative_uavs_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        main(["grass_running", "--uavs", "-1"])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--uavs must be >= 0 (0: the fire alone), got -1" in err[0]


@pytest.mark.slow
@pytest.mark.system
def test_process_runner_burns_the_same_area(tmp_path: Path, ros_env: dict[str, str]) -> None:
    """scripts/run_mission grass_running --uavs 0 over DDS: the in-process run's burned area."""
    r = subprocess.run(
        [sys.executable, "-m", "fire_mission.runner", "grass_running", "--uavs", "0", "--seed", "1"]
        + ["--max-duration", "8", "--out", str(tmp_path / "run"), "--quiet", "--no-record", "--no-report"],
        env=ros_env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
        cwd=ROOT,
    )
    assert r.returncode in (0, 1), r.stderr[-2000:]  # 1: time limit (a fire alone is never out)
    proc = json.loads((tmp_path / "run/summary.json").read_text())
    inproc = run_inprocess("grass_running", uavs=0, seed=1, overrides=SHORT)
    assert proc["uav_count"] == inproc["uav_count"] == 0
    assert proc["burned_area_m2"] == pytest.approx(inproc["burned_area_m2"], abs=0.0)
