"""run_mission rejects bad input with one clear line naming the problem, before starting anything."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _run(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    env = dict(
        os.environ,
        PYTHONPATH=os.pathsep.join(
            [
                str(ROOT / "tools"),
                str(ROOT / "ros2_ws/src/fire_uav_common"),
                os.environ.get("PYTHONPATH", ""),
            ]
        ),
    )
    return subprocess.run(
        [sys.executable, "-m", "fire_mission.runner", *args],
        env=env,
        capture_output=True,
        text=True,
        timeout=60,
        cwd=cwd,
    )


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["no_such_scenario"], "unknown scenario 'no_such_scenario'; shipped: .*ff_two_fires"),
        (["fault_drill", "--kill", "1at4"], "--kill expects K@T"),
        (["fault_drill", "--freeze", "1@5:4"], "--freeze expects K@T1:T2 with T2 > T1"),
        (["fault_drill", "--outage", "0>0@1:2", "--uavs", "3"], "both ends must be distinct"),
        (["fault_drill", "--loss", "1.5"], "--loss expects a probability in \\[0, 1\\]"),
        (["fault_drill", "--uavs", "3", "--kill", "5@4"], "fault names uav 5, but the fleet is uavs 0..2"),
        (["fault_drill", "--uavs", "-1"], "--uavs must be >= 0"),
        (["fault_drill", "--rtf", "-2"], "--rtf must be a positive number"),
        (["/nonexistent/x.yaml"], "scenario file not found: /nonexistent/x.yaml"),
    ],
)
def test_bad_arguments_are_named(args, message):
    r = _run(*args)
    assert r.returncode == 2, r.stderr
    import re

    assert re.search(message, r.stderr), r.stderr
    assert "Traceback" not in r.stderr


def test_bad_scenario_field_is_named(tmp_path):
    bad = tmp_path / "bad.yaml"
    text = (ROOT / "ros2_ws/src/fire_world_sim/scenarios/fault_drill.yaml").read_text()
    bad.write_text(text.replace("sigma_m: 60.0", "sigma_m: -3.0"))
    r = _run(str(bad))
    assert r.returncode == 2
    assert "bad.yaml" in r.stderr and "fires.analytic[0].sigma_m" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr


def test_lake_too_short_for_the_tankers_scoop_run_is_named():
    r = _run("fault_drill", "--set", "uavs.vehicle_model=coordinated_turn", "--set", "uavs.airframe=tanker")
    assert r.returncode == 2, r.stderr
    assert (
        "fault_drill.yaml: lakes[0].diameter_m: 90 m is shorter than the tanker preset's 702 m scoop run"
        in r.stderr
    ), r.stderr
    assert len(r.stderr.strip().splitlines()) == 1 and "Traceback" not in r.stderr


def test_outage_beyond_the_flown_fleet_is_named(tmp_path):
    """comms.outages is checked against --uavs, not only against the scenario's uavs.count."""
    sc = tmp_path / "outage.yaml"
    text = (ROOT / "ros2_ws/src/fire_world_sim/scenarios/fault_drill.yaml").read_text()
    sc.write_text(
        text.replace(
            "  loss_probability: 0.05",
            "  loss_probability: 0.05\n  outages: [{from: 0, to: 2, start_s: 1, end_s: 5}]",
        )
    )
    r = _run(str(sc), "--uavs", "2")
    assert r.returncode == 2, r.stderr
    assert (
        "outage.yaml: comms.outages[0].to: UAV 2 does not exist: the fleet has ids 0..1 (--uavs 2)"
        in r.stderr
    ), r.stderr
    assert "Traceback" not in r.stderr


def test_fleet_key_per_mission_private_and_only_where_needed(tmp_path):
    """A fresh key per mission, in the world's and agents' params files only, mode 0600."""
    import stat
    import sys as _sys

    _sys.path[:0] = [str(ROOT / "tools"), str(ROOT / "ros2_ws/src/fire_uav_common")]
    import yaml
    from fire_mission.runner import build_parser, write_params

    scen = ROOT / "ros2_ws/src/fire_world_sim/scenarios/fault_drill.yaml"
    keys = []
    for run in ("a", "b"):
        args = build_parser().parse_args(["fault_drill"])
        files = write_params(tmp_path / run, args, scen, 3, 1, None)
        got = set()
        for name, path in files.items():
            text = path.read_text()
            p = yaml.safe_load(text)["/**"]["ros__parameters"]
            if name == "recorder":
                assert "fleet_key" not in p
                continue
            assert stat.S_IMODE(path.stat().st_mode) == 0o600, name
            assert p["auth"] is True and len(p["fleet_key"]) == 64
            got.add(p["fleet_key"])
        assert len(got) == 1  # one fleet key for the world and every agent
        keys += got
    assert keys[0] != keys[1]
    off = write_params(
        tmp_path / "off", build_parser().parse_args(["fault_drill", "--no-auth"]), scen, 3, 1, None
    )
    p = yaml.safe_load(off["agent_0"].read_text())["/**"]["ros__parameters"]
    assert p["auth"] is False and "fleet_key" not in p


@pytest.mark.parametrize(
    ("outcome", "uavs", "user_limit", "status"),
    [
        ("complete", 5, None, 0),
        ("time_limit", 5, None, 1),  # the fleet ran out of the scenario's own time: a failure
        ("time_limit", 5, 20.0, 0),  # stopped where the user asked
        ("time_limit", 0, None, 0),  # the fire alone burns until the limit by design
        ("aborted", 5, 20.0, 1),
    ],
)
def test_exit_status_says_whether_the_mission_ended_as_asked(
    outcome: str, uavs: int, user_limit: float | None, status: int
) -> None:
    from fire_mission.cli import mission_exit_status

    assert mission_exit_status(outcome, uavs, user_limit) == status


def test_inprocess_max_duration_stops_there_and_exits_0(tmp_path: Path) -> None:
    from fire_mission.inprocess import main

    out = tmp_path / "s.json"
    assert main(["tiny_test", "--seed", "1", "--max-duration", "5", "--json", str(out)]) == 0
    import json

    d = json.loads(out.read_text())
    assert d["outcome"] == "time_limit" and d["mission_time_s"] == pytest.approx(5.0, abs=0.11)
