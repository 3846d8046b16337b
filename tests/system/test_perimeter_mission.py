"""PM perimeter monitoring end to end: a monitor is assigned, publishes its map, no crash."""

from __future__ import annotations

import pytest
from fire_uav_common.constants import EventType, Objective
from mission_util import ROOT, assert_no_survivors, run_mission

SCENARIO = ROOT / "ros2_ws/src/fire_world_sim/scenarios/monitor_grass.yaml"
MONITOR = Objective.MONITOR
CRASH = EventType.CRASH


@pytest.mark.system
@pytest.mark.slow
def test_monitor_is_assigned_and_mission_completes(tmp_path, ros_env, procs):
    summary, err = run_mission(
        tmp_path / "run", ros_env, str(SCENARIO), "--uavs", "3", "--no-record", timeout_s=120.0
    )
    events = summary.get("events", [])
    objectives = [e for e in events if e.get("type") == 12 and int(e.get("value", -1)) == MONITOR]
    assert objectives, f"no UAV switched to MONITOR; events: {events[:20]}"
    assert not [e for e in events if e.get("type") == CRASH], "a vehicle crashed"
    assert_no_survivors(summary)
