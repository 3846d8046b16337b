"""Live review: ``run_mission --foxglove`` serves the mission over Foxglove's WebSocket protocol.

A client that speaks the protocol (subprotocol ``foxglove.sdk.v1``, the ``websockets`` package)
connects while the mission runs, subscribes to ``/viz/world`` and ``/tf`` and decodes their
binary message frames with the schemas the server announced, using ``mcap-ros2-support``'s
decoder generator (independent of the rosbags code that wrote the schema text). The world runs
in realtime mode, which needs no start-up handshake.
"""

from __future__ import annotations

import asyncio
import json
import os
import signal
import socket
import struct
import subprocess
import sys
import time

import pytest
from mission_util import ROOT

pytestmark = [pytest.mark.system, pytest.mark.slow]

websockets = pytest.importorskip("websockets")
from mcap_ros2._dynamic import generate_dynamic  # noqa: E402


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _geojson_text(data: bytes) -> str:
    """foxglove.GeoJSON as protobuf: field 1 (``geojson``), a length-delimited UTF-8 string."""
    assert data[0] == 0x0A, data[:8]
    n, shift, i = 0, 0, 1
    while True:  # the length as a base-128 varint
        b = data[i]
        n |= (b & 0x7F) << shift
        shift, i = shift + 7, i + 1
        if not b & 0x80:
            break
    return data[i : i + n].decode()


def _decoder(ch: dict):
    if ch["schemaEncoding"] == "protobuf":
        assert ch["schemaName"] == "foxglove.GeoJSON", ch["schemaName"]
        return _geojson_text
    return generate_dynamic(ch["schemaName"], ch["schema"])[ch["schemaName"]]


async def _collect(port: int, want: dict[str, int], deadline: float) -> tuple[dict, dict]:
    """(advertised channels by topic, what came) once each topic has its count: ``messages`` and
    ``log_times`` by topic, and for a failure's message the ``subscribed`` topics (channel ids, in
    the order subscribed) and the server's ``status`` messages (an "Unknown channel ID" answers a
    subscription the server did not take). Subscribes to each wanted topic once, as Foxglove does:
    a failed subscription is not retried."""
    while True:
        try:
            # close_timeout: the SDK server now and then leaves a close frame unanswered (default 10 s)
            ws = await websockets.connect(
                f"ws://127.0.0.1:{port}", subprotocols=["foxglove.sdk.v1"], close_timeout=1.0
            )
            break
        except OSError:
            if time.monotonic() > deadline:
                raise
            await asyncio.sleep(0.5)
    channels: dict[str, dict] = {}
    subs: dict[int, str] = {}
    decoders: dict[str, object] = {}
    got: dict[str, list] = {t: [] for t in want}
    times: dict[str, list[int]] = {t: [] for t in want}
    subscribed: list[tuple[str, int]] = []
    statuses: list[str] = []
    async with ws:
        assert ws.subprotocol == "foxglove.sdk.v1"
        while time.monotonic() < deadline and any(len(v) < want[t] for t, v in got.items()):
            try:
                frame = await asyncio.wait_for(ws.recv(), timeout=1.0)
            except asyncio.TimeoutError:
                continue
            except websockets.exceptions.ConnectionClosed:
                break  # the mission ended (the runner stops the bridge): the counts below tell
            if isinstance(frame, str):
                msg = json.loads(frame)
                if msg.get("op") == "advertise":
                    new = []
                    for ch in msg["channels"]:
                        channels[ch["topic"]] = ch
                        if ch["topic"] in want and ch["topic"] not in subs.values():
                            sid = len(subs) + 1
                            subs[sid] = ch["topic"]
                            decoders[ch["topic"]] = _decoder(ch)
                            new.append({"id": sid, "channelId": ch["id"]})
                            subscribed.append((ch["topic"], ch["id"]))
                    if new:
                        await ws.send(json.dumps({"op": "subscribe", "subscriptions": new}))
                elif msg.get("op") == "status":
                    statuses.append(f"{msg.get('level')}: {msg.get('message')}")
                continue
            if frame[0] != 0x01:  # 0x02: server time broadcast
                continue
            sid, log_time = struct.unpack_from("<IQ", frame, 1)
            topic = subs.get(sid)
            if topic is not None and len(got[topic]) < want[topic]:
                got[topic].append(decoders[topic](frame[13:]))
                times[topic].append(log_time)
    return channels, {"messages": got, "log_times": times, "subscribed": subscribed, "statuses": statuses}


def _counts_and_why(channels: dict, got: dict, want: dict[str, int], out: str) -> str:
    """A failed count's message: the counts, what was advertised and subscribed, the server's
    status messages and the runner's output."""
    counts = {k: f"{len(v)} of {want[k]}" for k, v in got["messages"].items()}
    return (
        f"{counts}; advertised {len(channels)} channels: {sorted(channels)}; subscribed "
        f"(topic, channel id) {got['subscribed']}; server status {got['statuses']}\n{out[-3000:]}"
    )


def _run_and_collect(cmd: list[str], env: dict, port: int, want: dict[str, int]) -> tuple[dict, dict, str]:
    """Run the mission ``cmd``, :func:`_collect` ``want`` from its bridge on ``port`` within 120 s
    [wall], stop it: (advertised channels, what came, the runner's output). A bridge that never
    listened fails the test with the runner's output."""
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    channels: dict = {}
    got: dict = {}
    refused: OSError | None = None
    try:
        try:
            channels, got = asyncio.run(_collect(port, want, time.monotonic() + 120))
        except OSError as err:  # nothing listened on the port before the deadline
            refused = err
    finally:
        proc.send_signal(signal.SIGINT)
        try:
            out, _ = proc.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, _ = proc.communicate()
    if refused is not None:
        pytest.fail(f"no Foxglove server on 127.0.0.1:{port} within 120 s ({refused})\n{out[-3000:]}")
    return channels, got, out


def test_run_mission_foxglove_serves_viz_and_tf_with_their_schemas(ros_env, tmp_path):
    port = _free_port()
    env = dict(ros_env)
    env["PYTHONPATH"] = str(ROOT / "tools") + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("ROS_DOMAIN_ID", None)
    cmd = [sys.executable, "-m", "fire_mission.runner", "tiny_test", "--mode", "realtime", "--rtf", "1",
           "--max-duration", "60", "--foxglove", "--foxglove-port", str(port), "--out", str(tmp_path / "run"),
           "--quiet", "--no-report"]  # fmt: skip
    # /tf: the world (truth frames) and every agent (estimate frames) publish it, in any order.
    # Real time (rtf 1): the 53 s mission is the window to collect in (a loaded CI machine
    # once delivered too few at rtf 2 before the mission ended and the bridge closed)
    want = {"/viz/world": 3, "/tf": 30}
    channels, got, out = _run_and_collect(cmd, env, port, want)
    msgs = got["messages"]
    assert all(len(v) == want[k] for k, v in msgs.items()), _counts_and_why(channels, got, want, out)
    for topic, ros_type in (
        ("/viz/world", "visualization_msgs/msg/MarkerArray"),
        ("/tf", "tf2_msgs/msg/TFMessage"),
    ):
        ch = channels[topic]
        assert (ch["encoding"], ch["schemaName"], ch["schemaEncoding"]) == ("cdr", ros_type, "ros2msg")
    # every mission topic is served, not only the two subscribed
    assert {"/clock", "/world/truth", "/uav_0/sensors"} <= set(channels)
    arr = msgs["/viz/world"][-1]
    keys = {(m.ns, m.id) for m in arr.markers}
    assert {("uav", 0), ("uav", 1)} <= keys and all(m.header.frame_id == "map" for m in arr.markers)
    frames = {t.child_frame_id for m in msgs["/tf"] for t in m.transforms}
    assert {"uav_0", "uav_1"} <= frames  # the world's truth frames
    assert {"uav_0/estimate", "uav_1/estimate"} <= frames  # the agents' own estimates
    # log time is sim time (a mission starts at 0; wall-clock epoch would be > 1e18 ns)
    t = got["log_times"]["/viz/world"]
    assert all(0 <= x < 120 * 10**9 for x in t) and t == sorted(t)
    stamp = arr.markers[0].header.stamp
    assert abs(t[-1] - (stamp.sec * 10**9 + stamp.nanosec)) < 2 * 10**9
    # the bag of the same run reads as rosbag2's own, every message through rclpy's deserializer
    from fire_uav_recording.conformance import check_bag
    from fire_uav_recording.raw_topics import message_class
    from rclpy.serialization import deserialize_message

    classes: dict[str, type] = {}

    def rclpy_deserialize(msgtype: str, data: bytes) -> object:
        cls = classes.setdefault(msgtype, message_class(msgtype))
        return deserialize_message(data, cls)

    assert check_bag(tmp_path / "run" / "bag", deserialize=rclpy_deserialize) == []


def test_a_landscape_mission_serves_navsat_fixes_and_the_burned_area_for_the_map_panel(ros_env, tmp_path):
    """worcester_vt: each UAV's true position as NavSatFix and the burned area as GeoJSON, in
    degrees near Worcester, Vermont, beside the raw topics."""
    port = _free_port()
    env = dict(ros_env)
    env["PYTHONPATH"] = str(ROOT / "tools") + os.pathsep + env.get("PYTHONPATH", "")
    env.pop("ROS_DOMAIN_ID", None)
    cmd = [sys.executable, "-m", "fire_mission.runner", "worcester_vt", "--uavs", "2", "--mode", "realtime",
           "--rtf", "1", "--max-duration", "40", "--foxglove", "--foxglove-port", str(port),
           "--out", str(tmp_path / "run"), "--quiet", "--no-report", "--no-record"]  # fmt: skip
    want = {"/uav_0/geo/truth_fix": 5, "/uav_1/geo/truth_fix": 5, "/geo/fire_area": 2}
    channels, got, out = _run_and_collect(cmd, env, port, want)
    msgs = got["messages"]
    assert all(len(v) == want[k] for k, v in msgs.items()), _counts_and_why(channels, got, want, out)
    ch = channels["/uav_0/geo/truth_fix"]
    assert (ch["encoding"], ch["schemaName"], ch["schemaEncoding"]) == (
        "cdr",
        "sensor_msgs/msg/NavSatFix",
        "ros2msg",
    )
    assert (channels["/geo/fire_area"]["encoding"], channels["/geo/fire_area"]["schemaName"]) == (
        "protobuf",
        "foxglove.GeoJSON",
    )
    for k in (0, 1):
        for fix in msgs[f"/uav_{k}/geo/truth_fix"]:
            assert fix.header.frame_id == f"uav_{k}" and fix.status.status == 0
            assert 44.3 < fix.latitude < 44.4 and -72.6 < fix.longitude < -72.5 and 300 < fix.altitude < 800
    doc = json.loads(msgs["/geo/fire_area"][-1])
    burned = doc["features"][0]
    assert (
        burned["properties"]["name"] == "burned area" and burned["properties"]["area_m2"] > 2e4
    )  # about 3 ha lit
    lon, lat = zip(
        *(p for poly in burned["geometry"]["coordinates"] for ring in poly for p in ring), strict=True
    )
    assert 44.3 < min(lat) and max(lat) < 44.4 and -72.6 < min(lon) and max(lon) < -72.5
