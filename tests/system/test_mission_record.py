"""A recorded mission: the report computed from the bag agrees with what the runner saw live,
and replaying the bag republishes it on ROS topics."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time

import pytest
from mission_util import ROOT

pytestmark = [pytest.mark.system, pytest.mark.slow]


def test_recorded_mission_report_matches_live_and_replays(procs, ros_env, tmp_path):
    out = tmp_path / "run"
    env = dict(ros_env, PYTHONPATH=str(ROOT / "tools") + os.pathsep + ros_env.get("PYTHONPATH", ""))
    env.pop("ROS_DOMAIN_ID", None)
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "fire_mission.runner",
            "fault_drill",
            "--uavs",
            "3",
            "--seed",
            "7",
            "--kill",
            "2@4",
            "--out",
            str(out),
            "--quiet",
        ],
        env=env,
        capture_output=True,
        text=True,
        timeout=400,
        check=False,
    )
    live = json.loads((out / "summary.json").read_text())
    assert live["outcome"] == "complete", r.stderr[-3000:]
    assert (out / "bag" / "metadata.yaml").is_file()
    metrics = json.loads((out / "report" / "metrics.json").read_text())
    assert (out / "report" / "index.html").is_file()

    # the report, from the bag alone, agrees with the events the runner saw live
    assert metrics["outcome"] == live["outcome"]
    assert metrics["drop_count"] == live["drops_total"]
    assert metrics["drops_per_fire"] == live["drops_per_fire"]
    assert metrics["mean_inter_drop_interval_s"] == pytest.approx(
        live["mean_inter_drop_interval_s"], abs=1e-3
    )
    html = (out / "report" / "index.html").read_text()
    text = json.dumps(metrics)
    for c in live["crashes"]:
        assert str(c["uav_id"]) in text
    # the debrief's numbers are the console's: one computation each (packets, safety, containment)
    assert metrics["packets_lost_total"] == live["packets_lost"]
    assert sum(p["received"] for p in metrics["packets"].values()) == live["packets_received"]
    assert metrics["min_separation_m"] == pytest.approx(live["min_separation_m"], abs=1e-3)
    assert metrics["collisions"] == live["collisions"] and metrics["landed"] == live["landed"]
    assert metrics["landing_error_m"] == pytest.approx(live["landing_error_m"], abs=1e-3)
    assert metrics["contained_at_s"] == live["contained_at_s"]
    assert metrics["fires_active_at_end"] == live["fires_active_at_end"]
    # the kill is stated as an injected fault, with what the fleet did
    assert [(f["kind"], f["uav_id"]) for f in metrics["faults"]] == [("kill", 2)]
    assert "lost at" in html and "(injected)" in html and "its vehicle fell at" in html
    pngs = sorted(p.name for p in (out / "report").glob("*.png"))
    assert len(pngs) >= 5 and all(p in html for p in pngs)

    # replay at 20x on a private domain; a listener counts /world/truth messages
    procs.start("listener", [sys.executable, "-c", LISTENER, str(tmp_path / "count.txt")])
    time.sleep(1.0)
    rep = subprocess.run(
        [str(ROOT / "scripts/replay"), str(out / "bag"), "--rate", "20", "--delay", "3", "--no-progress"],
        env=procs.env,
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert rep.returncode == 0, rep.stderr[-2000:]
    time.sleep(1.0)
    procs.stop(["listener"])
    count = int((tmp_path / "count.txt").read_text() or 0)
    steps = round(live["mission_time_s"] / live["control_period_s"])
    assert count >= 0.9 * steps, f"replay delivered {count} truth messages of ~{steps}"


LISTENER = """
import sys, rclpy
from fire_uav_common import topics
from fire_uav_msgs.msg import WorldTruth
rclpy.init()
n = rclpy.create_node('replay_listener')
count = [0]
out = sys.argv[1]
def cb(m):
    count[0] += 1
    open(out, 'w').write(str(count[0]))
n.create_subscription(WorldTruth, topics.WORLD_TRUTH, cb, topics.qos('truth'))
open(out, 'w').write('0')
try:
    rclpy.spin(n)
except (KeyboardInterrupt, Exception):
    pass
"""
