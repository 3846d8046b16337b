"""A mission on a landscape, recorded and reported: the bag carries each UAV's true position as
NavSatFix beside every ``/world/truth`` (nothing lost, readable by rclpy), and the report draws
the ground and gives positions in latitude and longitude, as the runner's summary does."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest
from mission_util import ROOT

pytestmark = [pytest.mark.system, pytest.mark.slow]


def test_worcester_bag_has_a_fix_per_truth_and_vehicle_and_the_report_its_ground(ros_env, tmp_path):
    import fire_uav_recording as rec
    from fire_uav_recording.conformance import check_bag
    from fire_uav_recording.geo import geo_frame_of_bag
    from fire_uav_recording.raw_topics import message_class
    from rclpy.serialization import deserialize_message

    out = tmp_path / "run"
    env = dict(ros_env, PYTHONPATH=str(ROOT / "tools") + os.pathsep + ros_env.get("PYTHONPATH", ""))
    env.pop("ROS_DOMAIN_ID", None)
    r = subprocess.run(
        [sys.executable, "-m", "fire_mission.runner", "worcester_vt", "--uavs", "2", "--max-duration", "15",
         "--out", str(out), "--quiet"],
        env=env, capture_output=True, text=True, timeout=400, check=False,
    )  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    assert summary["outcome"] == "time_limit", r.stderr[-3000:]
    bag_path = out / "bag"
    with rec.open_bag(bag_path) as bag:
        assert bag.topics["/uav_0/geo/truth_fix"] == "sensor_msgs/msg/NavSatFix"
        truth = [m for _, _, m in bag.messages(["/world/truth"])]
        fixes: dict[str, list] = {}
        for topic, _, m in bag.messages(["/uav_0/geo/truth_fix", "/uav_1/geo/truth_fix"]):
            fixes.setdefault(topic, []).append(m)
    assert len(truth) >= 140  # 15 s at 10 control steps per second
    frame = geo_frame_of_bag(bag_path)
    assert frame is not None
    for k in (0, 1):
        got = fixes[f"/uav_{k}/geo/truth_fix"]
        want = [(t.header.stamp, v) for t in truth for v in t.vehicles if v.uav_id == k]
        assert len(got) == len(want)  # one fix per truth message and vehicle: none lost
        for fix, (stamp, v) in zip(got, want, strict=True):
            assert (fix.header.stamp.sec, fix.header.stamp.nanosec) == (stamp.sec, stamp.nanosec)
            lat, lon = frame.latlon(v.x_m, v.y_m)
            assert (fix.latitude, fix.longitude, fix.altitude) == (float(lat), float(lon), v.z_m)
        home = summary["geo"]["uav_homes"][k]
        assert (round(got[0].latitude, 6), round(got[0].longitude, 6)) == (home["lat_deg"], home["lon_deg"])

    classes: dict[str, type] = {}

    def rclpy_deserialize(msgtype: str, data: bytes) -> object:
        cls = classes.setdefault(msgtype, message_class(msgtype))
        return deserialize_message(data, cls)

    assert check_bag(bag_path, deserialize=rclpy_deserialize) == []

    metrics = json.loads((out / "report" / "metrics.json").read_text())
    assert metrics["figures"][0] == "landscape.png" and (out / "report" / "landscape.png").is_file()
    places = metrics["geo"]["places"]
    assert {p["kind"] for p in places} >= {"ignition", "fire", "lake", "home"}
    ign = [p for p in places if p["kind"] == "ignition"]
    assert [(p["lat_deg"], p["lon_deg"]) for p in ign] == [
        (g["lat_deg"], g["lon_deg"]) for g in summary["geo"]["ignitions"]
    ]
    homes = [p for p in places if p["kind"] == "home"]
    assert [(p["lat_deg"], p["lon_deg"]) for p in homes] == [
        (h["lat_deg"], h["lon_deg"]) for h in summary["geo"]["uav_homes"]
    ]
    html = (out / "report" / "index.html").read_text()
    assert 'id="places"' in html and "worcester_vt" in html
