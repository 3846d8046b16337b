"""The Foxglove bridge's channels of the fleet's topics exist before any client connects (rclpy in
this process on a private ROS domain, the bridge's WebSocket server on a free port, a client of
the protocol; no other process).

Why: foxglove-sdk 0.30.3 advertises a channel made while a client is connected before it takes
subscriptions to it, and answers a client that subscribes at once (as Foxglove does) "Unknown
channel ID": that client never gets the topic. A system test's client saw ``/tf`` 0 of 30 in about
one CI run of a dozen that way (the bridge's module docstring has the figures).
"""

from __future__ import annotations

import json
import re
import struct
import time

import pytest

ws_client = pytest.importorskip("websockets.sync.client")


def _recv(ws, timeout_s: float):
    """The next frame (text decoded as JSON), or None once ``timeout_s`` [s, wall] has passed."""
    try:
        frame = ws.recv(timeout=timeout_s)
    except TimeoutError:
        return None
    return json.loads(frame) if isinstance(frame, str) else frame


def test_up_front_topics_are_the_wanted_fleet_topics_of_the_fleet_size():
    from fire_uav_common import topics
    from fire_uav_recording.foxglove_bridge_node import up_front_topics

    served = dict(up_front_topics(2, lambda t: not re.fullmatch(r"/viz/.*", t)))
    assert served["/tf"] == "tf2_msgs/msg/TFMessage" and served["/uav_1/cmd"] == topics.CMD_SPEC.type
    assert "/uav_2/cmd" not in served and "/viz/world" not in served and "/uav_0/viz" in served
    per_vehicle = [s for s in topics.ALL_TOPICS if s.per_uav]
    assert len(served) == len(topics.ALL_TOPICS) - len(per_vehicle) - 3 + 2 * len(per_vehicle)  # 3 /viz/*
    assert up_front_topics(0, lambda t: True) == [
        (s.name, s.type) for s in topics.ALL_TOPICS if not s.per_uav
    ]


def test_a_client_connected_before_the_first_tf_gets_it_on_the_channel_it_subscribed_on_connecting(
    own_domain,
):
    """The client subscribes to ``/tf`` as it connects, before anyone publishes it; the bridge then
    finds the publisher and forwards its messages on that same channel, with no "Unknown channel
    ID" and no second advertisement of ``/tf``."""
    import rclpy
    from fire_uav_common import topics
    from fire_uav_recording.foxglove_bridge_node import FoxgloveBridgeNode
    from geometry_msgs.msg import TransformStamped
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.serialization import deserialize_message
    from tf2_msgs.msg import TFMessage

    args = ["-p", "port:=0", "-p", "uav_count:=2", "-p", "discovery_period_wall_s:=0.05"]
    rclpy.init(args=["--ros-args", *args], domain_id=own_domain)
    bridge = FoxgloveBridgeNode()
    source = rclpy.create_node("tf_source")
    executor = SingleThreadedExecutor()
    executor.add_node(bridge)
    executor.add_node(source)
    try:
        # close_timeout: the SDK's server now and then leaves the client's close frame unanswered
        # (2 closes in 30 here waited the default 10 s)
        url = f"ws://127.0.0.1:{bridge.server.port}"
        with ws_client.connect(url, subprotocols=["foxglove.sdk.v1"], close_timeout=0.5) as ws:
            channels: dict[str, dict] = {}
            while (msg := _recv(ws, 10.0)) is not None and msg.get("op") != "advertise":
                pass  # serverInfo first
            assert msg is not None, "no channel advertised to a client connecting before any publisher"
            channels.update({ch["topic"]: ch for ch in msg["channels"]})
            assert {"/tf", "/viz/world", "/clock", "/uav_1/cmd"} <= set(
                channels
            ) and "/uav_2/cmd" not in channels
            tf = channels["/tf"]
            assert (tf["encoding"], tf["schemaName"], tf["schemaEncoding"]) == (
                "cdr",
                "tf2_msgs/msg/TFMessage",
                "ros2msg",
            )
            ws.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 7, "channelId": tf["id"]}]}))
            pub = topics.publisher(source, topics.TF_SPEC)  # the first /tf publisher appears now
            t = TransformStamped(child_frame_id="uav_0")
            t.header.frame_id = "map"
            statuses: list[str] = []
            again: list[dict] = []
            got = None
            deadline = time.monotonic() + 20.0  # discovery, then DDS matching: well under a second here
            while got is None and time.monotonic() < deadline:
                pub.publish(TFMessage(transforms=[t]))
                executor.spin_once(timeout_sec=0.02)
                while (frame := _recv(ws, 0.0)) is not None:
                    if isinstance(frame, dict):
                        statuses += [frame["message"]] if frame.get("op") == "status" else []
                        again += [c for c in frame.get("channels", []) if c["topic"] == "/tf"]
                    elif frame[0] == 0x01 and struct.unpack_from("<I", frame, 1)[0] == 7:
                        got = deserialize_message(frame[13:], TFMessage)
                        break
            assert not statuses and not again, (statuses, again)
            assert got is not None, (
                f"no /tf message on the subscription made on connecting {bridge._follower.announced}"
            )
            assert [(x.header.frame_id, x.child_frame_id) for x in got.transforms] == [("map", "uav_0")]
    finally:
        executor.shutdown()
        bridge.close()
        source.destroy_node()
        bridge.destroy_node()


def test_a_fleet_name_published_with_another_type_is_served_as_that_type(own_domain):
    import rclpy
    from fire_uav_recording.foxglove_bridge_node import FoxgloveBridgeNode
    from fire_uav_recording.raw_topics import RawTopic
    from rclpy.qos import QoSProfile

    rclpy.init(args=["--ros-args", "-p", "port:=0", "-p", "uav_count:=1"], domain_id=own_domain)
    bridge = FoxgloveBridgeNode()
    try:
        made = bridge._channels["/fleet/events"]
        assert made.schema_name() == "fire_uav_msgs/msg/MissionEvent"
        same = RawTopic("/fleet/events", "fire_uav_msgs/msg/MissionEvent", None, (), QoSProfile(depth=10))
        assert bridge._on_topic(same) is not None and bridge._channels["/fleet/events"] is made
        other = RawTopic("/fleet/events", "std_msgs/msg/String", None, (), QoSProfile(depth=10))
        assert bridge._on_topic(other) is not None
        assert bridge._channels["/fleet/events"].schema_name() == "std_msgs/msg/String"
    finally:
        bridge.close()
        bridge.destroy_node()


def test_without_a_fleet_size_no_channel_is_made_before_its_topic_appears(own_domain):
    import rclpy
    from fire_uav_recording.foxglove_bridge_node import FoxgloveBridgeNode

    rclpy.init(args=["--ros-args", "-p", "port:=0"], domain_id=own_domain)
    bridge = FoxgloveBridgeNode()
    try:
        assert bridge._channels == {}
    finally:
        bridge.close()
        bridge.destroy_node()


def test_without_uav_count_the_fleet_is_the_scenarios(own_domain):
    from pathlib import Path

    import rclpy
    from fire_uav_common.scenario import load_scenario
    from fire_uav_recording.foxglove_bridge_node import FoxgloveBridgeNode

    scenario = Path(__file__).resolve().parents[2] / "fire_world_sim/scenarios/tiny_test.yaml"
    n = load_scenario(scenario).uavs.count
    assert n >= 1
    rclpy.init(args=["--ros-args", "-p", "port:=0", "-p", f"scenario_file:={scenario}"], domain_id=own_domain)
    bridge = FoxgloveBridgeNode()
    try:
        assert f"/uav_{n - 1}/sensors" in bridge._channels and f"/uav_{n}/sensors" not in bridge._channels
    finally:
        bridge.close()
        bridge.destroy_node()
